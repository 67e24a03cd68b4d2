// fuzz_shm_attach — the attach path against a hostile segment and a resizing adversary. Each input
// decides a segment's size, seals, mode and header bytes (a valid header XORed with the input);
// a real SessionServer serves it over a real socket and SegmentBuilder::open() attaches. An
// adversary holding the same descriptor truncates or grows it before and after the attach, then
// every page of the mapping is touched: a segment that could be resized under a reader would end
// in SIGBUS here, so open() must accept only sealed, exactly-sized, trusted segments.
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "rt_core/ipc/session_socket.hpp"
#include "rt_core/ipc/shm_segment.hpp"

namespace {

using namespace kerf::ipc;

struct Fixture {
    std::string runtime;
    unsigned char header[sizeof(SegmentHeader)] = {};  ///< a valid header, state running
    std::uint64_t session_id = 0;
};

const Fixture& fixture() {
    static const Fixture* f = [] {
        auto* out_ptr = new Fixture();
        Fixture& out = *out_ptr;
        char tmpl[] = "/tmp/kerf-fuzz-attach-XXXXXX";
        out.runtime = mkdtemp(tmpl);
        auto seg = SegmentBuilder().name("template").runtime_dir(out.runtime).create();
        if (!seg) std::abort();
        seg->layout().header.state.store(std::uint32_t(SegmentState::kRunning));
        std::memcpy(out.header, static_cast<const void*>(&seg->layout().header), sizeof out.header);
        out.session_id = seg->layout().header.session_id;
        return out_ptr;
    }();
    return *f;
}

off_t pick_size(std::uint8_t selector) {
    const off_t full = off_t(sizeof(SegmentLayout));
    switch (selector % 6) {
        case 0:
            return 0;
        case 1:
            return off_t(sizeof(SegmentHeader));
        case 2:
            return full - 4096;
        case 3:
            return full + 4096;
        default:
            return full;  // most inputs: the right size, so the deeper checks run
    }
}

// Resizes `fd` as an adversary would; harmless (refused) when the segment is sealed.
void resize(int fd, std::uint8_t how) {
    switch (how % 4) {
        case 0:
            (void)!ftruncate(fd, 0);
            break;
        case 1:
            (void)!ftruncate(fd, 4096);
            break;
        case 2:
            (void)!ftruncate(fd, off_t(2 * sizeof(SegmentLayout)));
            break;
        default:
            (void)!fallocate(fd, 0, 0, off_t(sizeof(SegmentLayout) + 4096));
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const Fixture& f = fixture();
    if (size < 4) return 0;
    const std::uint8_t flags = data[0], size_sel = data[1], before = data[2], after = data[3];
    data += 4;
    size -= 4;
    const int fd = memfd_create("kerf:fuzz", MFD_CLOEXEC | MFD_ALLOW_SEALING);
    if (fd < 0) return 0;
    const off_t bytes = pick_size(size_sel);
    if (ftruncate(fd, bytes) != 0) {
        close(fd);
        return 0;
    }
    unsigned char image[sizeof(SegmentHeader)];
    std::memcpy(image, f.header, sizeof image);
    for (std::size_t i = 0; i < size && i < sizeof image; ++i) image[i] ^= data[i];
    if (bytes >= off_t(sizeof image)) (void)!pwrite(fd, image, sizeof image, 0);
    int seals = 0;
    if (flags & 1) seals |= F_SEAL_SHRINK;
    if (flags & 2) seals |= F_SEAL_GROW;
    if (seals != 0) (void)fcntl(fd, F_ADD_SEALS, seals);
    (void)fchmod(fd, (flags & 4) ? 0666 : (flags & 8) ? 0660 : 0600);
    const int adversary = fcntl(fd, F_DUPFD_CLOEXEC, 0);
    PeerPolicy policy;
    policy.owner_uid = geteuid();
    auto server = SessionServer::start(f.runtime, "victim", fd, policy, f.session_id);
    if (!server) {
        close(adversary);
        return 0;
    }
    if (flags & 16) resize(adversary, before);
    auto opened = SegmentBuilder().name("victim").runtime_dir(f.runtime).open();
    if (std::getenv("KERF_FUZZ_VERBOSE") != nullptr) {
        std::fprintf(stderr, "attach: %s\n",
                     opened ? "accepted" : opened.error().message().c_str());
    }
    if (opened) {
        resize(adversary, after);
        // Touch every page: SIGBUS here means open() accepted a segment that could shrink.
        const auto* base = reinterpret_cast<const volatile unsigned char*>(&opened->layout());
        unsigned sum = 0;
        for (std::size_t at = 0; at < sizeof(SegmentLayout); at += 4096) sum += base[at];
        sum += base[sizeof(SegmentLayout) - 1];
        (void)sum;
        (void)producer_health(opened->layout());
    }
    close(adversary);
    return 0;
}
