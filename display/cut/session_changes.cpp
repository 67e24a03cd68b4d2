#include "display/cut/session_changes.hpp"

#include <algorithm>

namespace kerf::cut {

std::uint64_t SessionChanges::covered(const std::vector<IndexRange>& ranges) noexcept {
    std::uint64_t n = 0;
    for (const IndexRange& r : ranges) n += r.count;
    return n;
}

void SessionChanges::clear() noexcept {
    everything = poses = bodies = false;
    vertex_count = face_count = 0;
    vertices.clear();
    faces.clear();
}

void to_ranges(std::vector<std::uint32_t>& indices, std::uint32_t merge_gap,
               std::vector<IndexRange>& out) {
    out.clear();
    std::sort(indices.begin(), indices.end());
    for (const std::uint32_t i : indices) {
        if (!out.empty()) {
            IndexRange& last = out.back();
            const std::uint64_t end = std::uint64_t{last.first} + last.count;
            if (i < end) continue;
            if (i - end <= merge_gap) {
                last.count = i - last.first + 1;
                continue;
            }
        }
        out.push_back({i, 1});
    }
}

}  // namespace kerf::cut
