#include "display/mesh/bone_size.hpp"

#include <cmath>
#include <cstdio>

namespace kerf::mesh {

std::string bone_size_warning(double size_m, LengthUnit units) {
    if (!std::isfinite(size_m) || size_m <= 0) return {};
    if (size_m >= kMinBoneSize_m && size_m <= kMaxBoneSize_m) return {};
    const double in_file_units = size_m / metres_per_unit(units);
    char text[256];
    std::snprintf(text, sizeof text,
                  "the mesh is %.4g %s across (largest side), %s than a bone (%g mm .. %g m)",
                  in_file_units, std::string(to_string(units)).c_str(),
                  size_m < kMinBoneSize_m ? "smaller" : "larger", kMinBoneSize_m * 1000,
                  kMaxBoneSize_m);
    std::string out = text;
    // The unit that makes the file's numbers a plausible bone, most common first.
    for (LengthUnit u : {LengthUnit::kMillimetre, LengthUnit::kMetre, LengthUnit::kCentimetre,
                         LengthUnit::kInch, LengthUnit::kMicrometre}) {
        const double as_u = in_file_units * metres_per_unit(u);
        if (u == units || as_u < kMinBoneSize_m || as_u > kMaxBoneSize_m) continue;
        std::snprintf(text, sizeof text, ": is the file in %s? (--units %s reads it as %.4g mm)",
                      std::string(to_string(u)).c_str(), std::string(to_string(u)).c_str(),
                      as_u * 1000);
        return out + text;
    }
    return out;
}

}  // namespace kerf::mesh
