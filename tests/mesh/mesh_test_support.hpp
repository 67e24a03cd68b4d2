// Helpers shared by the mesh tests.
#pragma once

#include <cstddef>
#include <span>
#include <string_view>

namespace kerf::mesh {

/// The bytes of a string, for the in-memory parse entry points.
inline std::span<const std::byte> as_bytes(std::string_view s) {
    return {reinterpret_cast<const std::byte*>(s.data()), s.size()};
}

}  // namespace kerf::mesh
