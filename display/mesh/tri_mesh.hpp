// kerf::mesh::TriMesh — the one triangle-mesh type every Kerf module shares.
//
// An OpenMesh array-kernel triangle mesh in double precision (metres, like everything inside
// Kerf: loaders convert from the file's units), with per-vertex normal, planar texture
// coordinates, colour and a discrete material tag, per-face normals, and status bits on every
// element so that cuts can delete in place and compact only when asked (`garbage_collection()`).
// Create meshes with `make_mesh()` so that every attribute the cutting library interpolates exists.
#pragma once

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <cstdint>
#include <string_view>

namespace kerf::mesh {

/// What a vertex is made of. Cutting interpolates continuous attributes; a cut point takes the
/// nearer endpoint's material (the lower-index one at t = 0.5) and its rim copy the same, so a
/// cap's corners (every one a rim vertex, shared with the piece's side faces) keep the material
/// of the surface they lie on. Which faces are caps is the cut library's face property
/// (cut::kCapFaceProperty), not a vertex material: the renderer draws a cap corner as cut
/// cortical or cut canal bone by this material, and the collision export makes cap faces
/// kCutSurface and faces whose corners are all kCancellous the canal.
enum class Material : std::uint8_t {
    kCortical = 0,    ///< dense outer bone
    kCancellous = 1,  ///< spongy inner bone (medullary canal wall)
    kCutSurface = 2,  ///< cut bone; no cut sets it on a vertex (a PLY file may carry it)
};
std::string_view to_string(Material m) noexcept;

struct MeshTraits : public OpenMesh::DefaultTraits {
    using Point = OpenMesh::Vec3d;
    using Normal = OpenMesh::Vec3d;
    using TexCoord2D = OpenMesh::Vec2f;
    using Color = OpenMesh::Vec3f;

    VertexAttributes(OpenMesh::Attributes::Normal | OpenMesh::Attributes::TexCoord2D |
                     OpenMesh::Attributes::Color | OpenMesh::Attributes::Status);
    FaceAttributes(OpenMesh::Attributes::Normal | OpenMesh::Attributes::Status);
    EdgeAttributes(OpenMesh::Attributes::Status);
    HalfedgeAttributes(OpenMesh::Attributes::PrevHalfedge | OpenMesh::Attributes::Status);

    VertexTraits {
    public:
        Material material() const { return material_; }
        void set_material(Material m) { material_ = m; }

    private:
        Material material_ = Material::kCortical;
    };
};

using TriMesh = OpenMesh::TriMesh_ArrayKernelT<MeshTraits>;
using Point = TriMesh::Point;
using VertexHandle = OpenMesh::VertexHandle;
using FaceHandle = OpenMesh::FaceHandle;
using HalfedgeHandle = OpenMesh::HalfedgeHandle;
using EdgeHandle = OpenMesh::EdgeHandle;

/// An empty mesh with every attribute Kerf uses already requested (they are in the traits, so
/// this is just a named constructor that reads well at call sites).
inline TriMesh make_mesh() { return TriMesh{}; }

}  // namespace kerf::mesh
