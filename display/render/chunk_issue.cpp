#include "display/render/chunk_issue.hpp"

#include <algorithm>

namespace kerf::render {

namespace {

constexpr std::uint32_t kChunk = kBoneChunkTriangles;

std::uint32_t chunks_of(std::uint32_t triangles) noexcept {
    return (triangles + kChunk - 1) / kChunk;
}

}  // namespace

std::uint32_t ChunkIssue::chunk_end(std::uint32_t c) const noexcept {
    return std::min((c + 1) * kChunk, triangles_);
}

bool ChunkIssue::hot(std::uint32_t c) const noexcept {
    return c < edited_.size() && edited_[c] != 0 && stamp_ - edited_[c] < kHotUploads;
}

void ChunkIssue::mark_hot(std::uint32_t c) {
    if (c >= edited_.size()) edited_.resize(c + 1, 0);
    if (stamp_ == 0) stamp_ = 1;
    edited_[c] = stamp_;
}

void ChunkIssue::plan() {
    pending_.clear();
    at_ = 0;
    const std::uint32_t chunks = chunks_of(triangles_);
    for (int pass = 0; pass < 2; ++pass) {
        for (std::uint32_t c = 0; c < chunks; ++c) {
            if (c * kChunk + done_[c] >= chunk_end(c)) continue;  // issued whole
            if (hot(c) == (pass == 1)) pending_.push_back(c);
        }
    }
}

void ChunkIssue::uploaded(const RenderMesh& mesh) {
    triangles_ = mesh.triangle_count();
    vertex_limit_ = mesh.vertex_count();
    vertex_capacity_ = mesh.vertex_capacity();
    cap_limit_ = mesh.cap_vertex_count();
    generation_ = mesh.generation();
    done_.resize(chunks_of(triangles_), 0);
    plan();
}

void ChunkIssue::begin() {
    std::fill(done_.begin(), done_.end(), 0);
    plan();
}

bool ChunkIssue::next(std::uint32_t& first, std::uint32_t& count) {
    while (at_ < pending_.size()) {
        const std::uint32_t c = pending_[at_++];
        const std::uint32_t start = c * kChunk + done_[c], end = chunk_end(c);
        if (start >= end) continue;
        first = start;
        count = end - start;
        done_[c] = end - c * kChunk;
        return true;
    }
    return false;
}

void ChunkIssue::note_edits(RenderMesh& mesh) {
    if (mesh.needs_realloc() || mesh.dirty_indices().empty()) return;
    ++stamp_;
    if (stamp_ == 0) stamp_ = 1;
    for (const auto& r : mesh.dirty_indices().ranges()) {
        const std::uint32_t t0 = r.first / 3, t1 = (r.first + r.count + 2) / 3;
        for (std::uint32_t c = t0 / kChunk; c * kChunk < t1; ++c) mark_hot(c);
    }
}

bool ChunkIssue::can_join(RenderMesh& mesh) {
    if (mesh.needs_realloc() || mesh.generation() != generation_ ||
        mesh.vertex_capacity() != vertex_capacity_) {
        return false;
    }
    bool clear = true;
    for (const auto& r : mesh.dirty_indices().ranges()) {
        const std::uint32_t t0 = r.first / 3, t1 = (r.first + r.count + 2) / 3;
        for (std::uint32_t c = t0 / kChunk; c * kChunk < t1 && c < done_.size(); ++c) {
            if (done_[c] > 0 && t0 < c * kChunk + done_[c]) {  // [c*C, c*C + done) meets [t0, t1)
                mark_hot(c);
                clear = false;
            }
        }
    }
    if (!clear) return false;
    // Dirty vertices the issued triangles cannot have used (appended since their upload) are
    // fine; any other one is looked for in the issued triangles' indices.
    const auto fresh = [&](const DirtyRanges::Range& r) {
        const std::uint64_t end = std::uint64_t{r.first} + r.count;
        return (r.first >= vertex_limit_ && end <= vertex_capacity_) ||
               std::uint64_t{r.first} >= std::uint64_t{vertex_capacity_} + cap_limit_;
    };
    const auto ranges = mesh.dirty_vertices().ranges();
    if (std::all_of(ranges.begin(), ranges.end(), fresh)) return true;
    bits_.resize(mesh.vertices().size() / 64 + 1, 0);
    for (const auto& r : ranges) {
        if (fresh(r)) continue;
        for (std::uint32_t v = r.first; v < r.first + r.count; ++v)
            bits_[v >> 6] |= std::uint64_t{1} << (v & 63);
    }
    const auto indices = mesh.indices();
    for (std::uint32_t c = 0; c < done_.size(); ++c) {
        const std::size_t begin = std::size_t{c} * kChunk * 3, end = begin + done_[c] * 3u;
        for (std::size_t i = begin; i < end && i < indices.size(); ++i) {
            const std::uint32_t v = indices[i];
            if (v < bits_.size() * 64 && (bits_[v >> 6] >> (v & 63)) & 1) {
                mark_hot(c);
                clear = false;
                break;
            }
        }
    }
    for (const auto& r : ranges) {
        if (fresh(r)) continue;
        for (std::uint32_t v = r.first; v < r.first + r.count; ++v) bits_[v >> 6] = 0;
    }
    return clear;
}

}  // namespace kerf::render
