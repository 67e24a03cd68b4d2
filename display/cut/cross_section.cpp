#include "display/cut/cross_section.hpp"

namespace kerf::cut {

void CrossSection::clear() noexcept {
    for (CrossSectionSide* side : {&positive, &negative}) {
        side->loops.clear();
        side->cap_vertices.clear();
        side->cap_faces.clear();
    }
    loops_2d.clear();
    loop_is_hole.clear();
}

}  // namespace kerf::cut
