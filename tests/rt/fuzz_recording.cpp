// fuzz_recording — random bytes as a kerf-rt input recording (kerf replay reads recordings made on
// other machines): the loader must refuse what is malformed, naming it, and whatever it accepts
// must replay without a crash, every sample finite and every status, timing and device generation
// in range. With the first byte odd the header is made valid (magic, a version from 1 to the
// current, sizes, record count), so the fuzzer spends its time on the records.
#include <sys/mman.h>
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "rt_core/loop/input_recording.hpp"

namespace {

using namespace kerf::rt;

void check(bool ok) {
    if (!ok) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0 || size > (1u << 20)) return 0;
    std::vector<std::uint8_t> bytes(data + 1, data + size);
    if ((data[0] & 1) != 0) {  // a valid header over whatever records follow
        bytes.resize(sizeof(RecordingHeader) +
                     (bytes.size() / sizeof(RecordedInput)) * sizeof(RecordedInput));
        RecordingHeader h{};
        std::memcpy(h.magic, kRecordingMagic, sizeof h.magic);
        h.version = 1 + std::uint32_t(data[0] >> 1) % kRecordingVersion;  // every version read
        h.record_size = sizeof(RecordedInput);
        h.period_ns = 1'000'000;
        h.records = (bytes.size() - sizeof h) / sizeof(RecordedInput);
        std::memcpy(bytes.data(), &h, sizeof h);
        for (std::uint64_t i = 0; i < h.records; ++i) {  // ticks in order, or every record fails
            const std::size_t at = sizeof h + i * sizeof(RecordedInput);
            std::memcpy(bytes.data() + at + offsetof(RecordedInput, tick), &i, sizeof i);
        }
    }
    const int fd = memfd_create("fuzz-recording", 0);
    if (fd < 0) return 0;
    if (!bytes.empty() && write(fd, bytes.data(), bytes.size()) != ssize_t(bytes.size())) {
        close(fd);
        return 0;
    }
    const std::string path = "/proc/self/fd/" + std::to_string(fd);
    auto loaded = load_recording(path);
    close(fd);
    if (!loaded) {
        check(loaded.error().find("recording ") == 0);  // names the file
        return 0;
    }
    ReplayDevice replay(*loaded, {});
    kerf::firmware_host::DeviceSample sample;
    for (std::size_t i = 0; i < loaded->inputs.size(); ++i) {
        const auto status = replay.try_read(sample, 0);
        check(std::uint8_t(status) <= std::uint8_t(kerf::firmware_host::DeviceStatus::kError));
        const RecordedTiming t = replay.recorded_timing();
        check(t.missed_deadlines <= 1'000'000);
        // One re-open a tick at most, tick 0 included: the next tick's generation is at most i + 2.
        check(replay.device_generation_due() <= i + 2);
        if (status != kerf::firmware_host::DeviceStatus::kOk) continue;
        for (int k = 0; k < 3; ++k)
            check(std::isfinite(sample.position_m[k]) && std::isfinite(sample.velocity_m_per_s[k]));
    }
    check(replay.try_read(sample, 0) == kerf::firmware_host::DeviceStatus::kDisconnected);
    return 0;
}
