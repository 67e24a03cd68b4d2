#include "display/cut/face_grid.hpp"

#include <algorithm>
#include <cmath>

namespace kerf::cut::detail {

namespace {

constexpr double kCellsPerFaceSize = 3.0;
constexpr std::size_t kMaxCells = std::size_t{1} << 22;

void face_box(const mesh::TriMesh& m, mesh::FaceHandle f, Vec3& lo, Vec3& hi) {
    lo = Vec3(1e300, 1e300, 1e300);
    hi = Vec3(-1e300, -1e300, -1e300);
    for (auto v : m.fv_range(f)) {
        lo.minimize(m.point(v));
        hi.maximize(m.point(v));
    }
}

}  // namespace

FaceGrid::Entry FaceGrid::entry_of(const mesh::TriMesh& mesh, mesh::FaceHandle f) {
    Vec3 p[3];
    int k = 0;
    for (auto v : mesh.fv_range(f)) p[k++] = mesh.point(v);
    const Vec3 c = (p[0] + p[1] + p[2]) / 3.0;
    double r = std::max({(p[0] - c).norm(), (p[1] - c).norm(), (p[2] - c).norm()});
    // float rounding of the centre: pad by a few ulps of the coordinates.
    r += 4e-7 * (std::abs(c[0]) + std::abs(c[1]) + std::abs(c[2])) + 1e-12;
    Entry e;
    e.face = f.idx();
    for (int a = 0; a < 3; ++a) e.centre[a] = static_cast<float>(c[a]);
    e.radius = static_cast<float>(r * (1.0 + 1e-6));
    return e;
}

int FaceGrid::clamp_cell(double x, int axis) const noexcept {
    const double c = std::floor((x - origin_[axis]) / cell_m_);
    if (!(c >= 0.0)) return 0;
    return static_cast<int>(std::min(c, static_cast<double>(dims_[axis] - 1)));
}

void FaceGrid::build(const mesh::TriMesh& mesh) {
    Vec3 lo(1e300, 1e300, 1e300), hi(-1e300, -1e300, -1e300);
    double size_sum = 0.0;
    std::size_t n = 0;
    for (auto f : mesh.faces()) {
        Vec3 a, b;
        face_box(mesh, f, a, b);
        lo.minimize(a);
        hi.maximize(b);
        size_sum += (b - a).max();
        ++n;
    }
    margin_m_ = 0.0;
    if (n == 0) {
        offsets_.clear(), faces_.clear(), extra_head_.clear(), extra_.clear();
        return;
    }
    const Vec3 ext = hi - lo;
    const double diag = std::max(ext.norm(), 1e-12);
    cell_m_ = std::max(kCellsPerFaceSize * size_sum / static_cast<double>(n), diag * 1e-6);
    auto cells_for = [&](double c) {
        double total = 1.0;
        for (int a = 0; a < 3; ++a) total *= std::floor(ext[a] / c) + 1.0;
        return total;
    };
    while (cells_for(cell_m_) > static_cast<double>(kMaxCells)) cell_m_ *= 1.25;
    origin_ = lo;
    for (int a = 0; a < 3; ++a) dims_[a] = static_cast<int>(std::floor(ext[a] / cell_m_)) + 1;
    const std::size_t cells = static_cast<std::size_t>(dims_[0]) * dims_[1] * dims_[2];
    offsets_.assign(cells + 1, 0);
    auto for_cells = [&](mesh::FaceHandle f, auto&& fn) {
        Vec3 a, b;
        face_box(mesh, f, a, b);
        const int i0 = clamp_cell(a[0], 0), i1 = clamp_cell(b[0], 0);
        const int j0 = clamp_cell(a[1], 1), j1 = clamp_cell(b[1], 1);
        const int k0 = clamp_cell(a[2], 2), k1 = clamp_cell(b[2], 2);
        for (int k = k0; k <= k1; ++k)
            for (int j = j0; j <= j1; ++j)
                for (int i = i0; i <= i1; ++i) fn(cell_id(i, j, k));
    };
    for (auto f : mesh.faces()) for_cells(f, [&](std::size_t c) { ++offsets_[c + 1]; });
    for (std::size_t c = 0; c < cells; ++c) offsets_[c + 1] += offsets_[c];
    faces_.resize(offsets_[cells]);
    std::vector<std::uint32_t> fill(offsets_.begin(), offsets_.end() - 1);
    for (auto f : mesh.faces()) {
        const Entry e = entry_of(mesh, f);
        for_cells(f, [&](std::size_t c) { faces_[fill[c]++] = e; });
    }
    extra_head_.assign(cells, -1);
    extra_.clear();
}

void FaceGrid::reserve_resident(std::size_t faces) {
    const std::size_t n = extra_.size();
    extra_.resize(n + 2 * faces);  // value-initialised: every page written
    extra_.resize(n);
}

void FaceGrid::insert(const mesh::TriMesh& mesh, mesh::FaceHandle f) {
    if (offsets_.empty()) return;
    Vec3 a, b;
    face_box(mesh, f, a, b);
    const Entry e = entry_of(mesh, f);
    const int i0 = clamp_cell(a[0], 0), i1 = clamp_cell(b[0], 0);
    const int j0 = clamp_cell(a[1], 1), j1 = clamp_cell(b[1], 1);
    const int k0 = clamp_cell(a[2], 2), k1 = clamp_cell(b[2], 2);
    for (int k = k0; k <= k1; ++k)
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) {
                const std::size_t c = cell_id(i, j, k);
                extra_.push_back(Node{e, extra_head_[c]});
                extra_head_[c] = static_cast<std::int32_t>(extra_.size() - 1);
            }
}

}  // namespace kerf::cut::detail
