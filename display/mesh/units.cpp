#include "display/mesh/units.hpp"

namespace kerf::mesh {

double metres_per_unit(Units u) noexcept {
    switch (u) {
        case Units::kMetres:
            return 1.0;
        case Units::kMillimetres:
            return 0.001;
        case Units::kCentimetres:
            return 0.01;
        case Units::kInches:
            return 0.0254;
        case Units::kMicrometres:
            return 1e-6;
    }
    return 1.0;
}

std::string_view to_string(Units u) noexcept {
    switch (u) {
        case Units::kMetres:
            return "m";
        case Units::kMillimetres:
            return "mm";
        case Units::kCentimetres:
            return "cm";
        case Units::kInches:
            return "in";
        case Units::kMicrometres:
            return "um";
    }
    return "unknown";
}

std::optional<Units> parse_units(std::string_view text) noexcept {
    for (Units u : {Units::kMetres, Units::kMillimetres, Units::kCentimetres, Units::kInches,
                    Units::kMicrometres}) {
        if (text == to_string(u)) return u;
    }
    return std::nullopt;
}

}  // namespace kerf::mesh
