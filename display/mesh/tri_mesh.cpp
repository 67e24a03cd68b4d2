#include "display/mesh/tri_mesh.hpp"

namespace kerf::mesh {

std::string_view to_string(Material m) noexcept {
    switch (m) {
        case Material::kCortical:
            return "cortical";
        case Material::kCancellous:
            return "cancellous";
        case Material::kCutSurface:
            return "cut_surface";
    }
    return "unknown";
}

}  // namespace kerf::mesh
