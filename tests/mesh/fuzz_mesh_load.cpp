// libFuzzer target for the mesh loaders. The first byte picks the format (stl, obj, ply, off);
// the rest is the file. Each accepted input also goes through OpenMesh (build_tri_mesh) and the
// validator, so hostile topology is exercised too.
#include <cstddef>
#include <cstdint>
#include <span>

#include "display/mesh/mesh_io.hpp"
#include "display/mesh/validate.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace kerf::mesh;
    if (size == 0) return 0;
    constexpr Format kFormats[] = {Format::kStl, Format::kObj, Format::kPly, Format::kOff};
    const Format format = kFormats[data[0] % 4];
    const std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data + 1), size - 1);
    auto loaded = parse_mesh(bytes, format, kerf::LengthUnit::kMillimetre, "fuzz");
    if (loaded) {
        const ValidationReport r = validate(loaded->indexed);
        if (r.triangles != loaded->mesh.n_faces()) __builtin_trap();  // nothing may be dropped
    } else if (loaded.error().message().empty()) {
        __builtin_trap();
    }
    return 0;
}
