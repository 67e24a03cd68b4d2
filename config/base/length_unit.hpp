// kerf::LengthUnit — the length unit a file states: a mesh file's coordinates, a scene's
// `units = "mm"`, `kerf mesh --units`. Inside Kerf every length is in metres: readers multiply by
// metres_per_unit(), writers divide by it. Header-only, part of kerf_base.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

namespace kerf {

/// A length unit a file may be written in.
enum class LengthUnit : std::uint8_t { kMetre, kCentimetre, kMillimetre, kMicrometre, kInch };

/// Every unit, in declaration order (the order accepted names are listed in).
inline constexpr std::array<LengthUnit, 5> kLengthUnits = {
    LengthUnit::kMetre, LengthUnit::kCentimetre, LengthUnit::kMillimetre, LengthUnit::kMicrometre,
    LengthUnit::kInch};

/// Short name, as on the command line and in scene files: "m", "cm", "mm", "um", "in".
constexpr std::string_view to_string(LengthUnit unit) noexcept {
    switch (unit) {
        case LengthUnit::kMetre:
            return "m";
        case LengthUnit::kCentimetre:
            return "cm";
        case LengthUnit::kMillimetre:
            return "mm";
        case LengthUnit::kMicrometre:
            return "um";
        case LengthUnit::kInch:
            return "in";
    }
    return "unknown";
}

/// How many metres one unit is (mm -> 0.001, in -> 0.0254).
constexpr double metres_per_unit(LengthUnit unit) noexcept {
    switch (unit) {
        case LengthUnit::kMetre:
            return 1.0;
        case LengthUnit::kCentimetre:
            return 0.01;
        case LengthUnit::kMillimetre:
            return 0.001;
        case LengthUnit::kMicrometre:
            return 1e-6;
        case LengthUnit::kInch:
            return 0.0254;
    }
    return 1.0;
}

/// The unit a short name ("m", "cm", "mm", "um", "in") names; nullopt for anything else.
constexpr std::optional<LengthUnit> parse_length_unit(std::string_view text) noexcept {
    for (const LengthUnit unit : kLengthUnits) {
        if (text == to_string(unit)) return unit;
    }
    return std::nullopt;
}

}  // namespace kerf
