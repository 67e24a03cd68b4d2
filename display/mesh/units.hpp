// kerf::mesh::Units — the length unit a mesh file is written in. Inside Kerf every length is in
// metres; loaders multiply by `metres_per_unit()` and writers divide by it.
#pragma once

#include <optional>
#include <string_view>

namespace kerf::mesh {

enum class Units {
    kMetres,
    kMillimetres,
    kCentimetres,
    kInches,
    kMicrometres,
};

/// How many metres one file unit is (mm -> 0.001, in -> 0.0254).
double metres_per_unit(Units u) noexcept;

/// Short name as used on the command line and in scene files: "m", "mm", "cm", "in", "um".
std::string_view to_string(Units u) noexcept;

/// Parses "m", "mm", "cm", "in" or "um"; nullopt for anything else.
std::optional<Units> parse_units(std::string_view text) noexcept;

}  // namespace kerf::mesh
