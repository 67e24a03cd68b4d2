#include "rt_core/loop/input_recording.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "rt_core/loop/haptic_loop.hpp"

namespace kerf::rt {
namespace {

using firmware_host::DeviceSample;
using firmware_host::DeviceStatus;

/// Most missed deadlines one record may say (a 1,000-s stall at 1 kHz; a recorder clamps to it).
constexpr std::uint64_t kMaxMissed = 1'000'000;

std::uint8_t flag_bits(const firmware_host::DeviceFlags& f) noexcept {
    return std::uint8_t((f.homed ? 1 : 0) | (f.amplifiers_on ? 2 : 0) | (f.estop ? 4 : 0) |
                        (f.watchdog_tripped ? 8 : 0) | (f.encoder_fault ? 16 : 0) |
                        (f.over_temperature ? 32 : 0));
}

firmware_host::DeviceFlags flags_from(std::uint8_t b) noexcept {
    firmware_host::DeviceFlags f;
    f.homed = b & 1, f.amplifiers_on = b & 2, f.estop = b & 4;
    f.watchdog_tripped = b & 8, f.encoder_fault = b & 16, f.over_temperature = b & 32;
    return f;
}

bool finite(const double* v, int n) noexcept {
    for (int i = 0; i < n; ++i)
        if (!std::isfinite(v[i])) return false;
    return true;
}

}  // namespace

Result<std::unique_ptr<InputRecorder>, std::string> InputRecorder::start(const std::string& path,
                                                                         std::uint64_t period_ns,
                                                                         WhenFull when_full) {
    std::unique_ptr<InputRecorder> r(new InputRecorder());
    r->when_full_ = when_full;
    r->ring_ = std::make_unique<Ring>();
    r->producer_ =
        ipc::SpscProducerEnd<RecordedInput, kCapacity>(&r->ring_->control, r->ring_->slots);
    r->consumer_ =
        ipc::SpscConsumerEnd<RecordedInput, kCapacity>(&r->ring_->control, r->ring_->slots);
    r->path_ = path;
    r->file_ = std::fopen((path + ".tmp").c_str(), "wb");
    if (!r->file_) return Err{"recording " + path + ".tmp: " + std::strerror(errno)};
    std::memcpy(r->header_.magic, kRecordingMagic, sizeof r->header_.magic);
    r->header_.version = kRecordingVersion;
    r->header_.record_size = sizeof(RecordedInput);
    r->header_.period_ns = period_ns;
    r->write_failed_ = std::fwrite(&r->header_, sizeof r->header_, 1, r->file_) != 1;
    InputRecorder* self = r.get();
    r->thread_ = std::thread([self] {
        while (!self->stop_.load(std::memory_order_acquire)) {
            self->drain();
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
    });
    return r;
}

InputRecorder::~InputRecorder() { (void)stop(); }

void InputRecorder::drain() noexcept {
    RecordedInput in;
    while (consumer_.try_pop(in) == ipc::PopResult::kOk) {
        if (std::fwrite(&in, sizeof in, 1, file_) != 1) write_failed_ = true;
        ++header_.records;
    }
}

Result<std::uint64_t, std::string> InputRecorder::stop() {
    if (stopped_) return header_.records;
    stopped_ = true;
    stop_.store(true, std::memory_order_release);
    if (thread_.joinable()) thread_.join();
    drain();
    header_.dropped = producer_.dropped();
    bool ok = !write_failed_ && std::fseek(file_, 0, SEEK_SET) == 0 &&
              std::fwrite(&header_, sizeof header_, 1, file_) == 1 && std::fflush(file_) == 0;
    ok = std::fclose(file_) == 0 && ok;
    file_ = nullptr;
    std::error_code ec;
    if (ok && !header_.dropped) std::filesystem::rename(path_ + ".tmp", path_, ec);
    if (!ok || ec || header_.dropped) std::filesystem::remove(path_ + ".tmp", ec);
    if (header_.dropped)
        return Err{"recording " + path_ + ": " + std::to_string(header_.dropped) +
                   " ticks dropped (the drain thread fell behind); not kept, it could not be "
                   "replayed"};
    if (!ok || ec) return Err{"recording " + path_ + ": write failed"};
    return header_.records;
}

void InputRecorder::record(const TickSeen& seen) noexcept {
    const DeviceSample& out = *seen.sample;
    RecordedInput r{};
    r.tick = seen.tick;
    r.world_generation = seen.world_generation;
    r.device_generation = std::uint32_t(std::min<std::uint64_t>(seen.device_generation, ~0u));
    r.sample_count = out.count;
    r.device_sequence = out.device_sequence;
    r.buttons = out.buttons;
    for (int i = 0; i < 3; ++i) {
        r.position_m[i] = out.position_m[i];
        r.velocity_m_per_s[i] = out.velocity_m_per_s[i];
    }
    for (int i = 0; i < 4; ++i) r.orientation_wxyz[i] = out.orientation_wxyz[i];
    r.command_lag = out.command_lag;
    r.status = std::uint8_t(seen.status);
    r.flags = flag_bits(out.flags);
    r.has_orientation = out.has_orientation ? 1 : 0;
    r.overran_last = seen.timing.overran_last ? 1 : 0;
    r.missed_deadlines =
        std::uint32_t(std::min<std::uint64_t>(seen.timing.missed_deadlines, kMaxMissed));
    if (when_full_ == WhenFull::kWait)
        push_waiting(r);
    else
        try_push(r);
}

bool InputRecorder::push_waiting(const RecordedInput& input) noexcept {
    const auto give_up = std::chrono::steady_clock::now() + kMaxWaitWhenFull;
    while (producer_.full() && std::chrono::steady_clock::now() < give_up)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    return try_push(input);
}

Result<Recording, std::string> load_recording(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) return Err{"recording " + path + ": not a regular file"};
    const auto size = fs::file_size(path, ec);
    if (ec || size < sizeof(RecordingHeader))
        return Err{"recording " + path + ": shorter than its header"};
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) return Err{"recording " + path + ": " + std::strerror(errno)};
    RecordingHeader h{};
    Recording out;
    const bool head_ok = std::fread(&h, sizeof h, 1, f) == 1;
    const auto fail = [&](const std::string& what) {
        std::fclose(f);
        return Err{"recording " + path + ": " + what};
    };
    if (!head_ok || std::memcmp(h.magic, kRecordingMagic, sizeof h.magic) != 0)
        return fail("not a Kerf input recording (bad magic)");
    if (h.version < 1 || h.version > kRecordingVersion || h.record_size != sizeof(RecordedInput))
        return fail("version " + std::to_string(h.version) + " / record size " +
                    std::to_string(h.record_size) + " (expected " + "1 to " +
                    std::to_string(kRecordingVersion) + " / " +
                    std::to_string(sizeof(RecordedInput)) + ")");
    if (h.dropped) return fail(std::to_string(h.dropped) + " ticks were dropped when recording");
    if (h.period_ns < 10'000 || h.period_ns > 1'000'000'000)
        return fail("period " + std::to_string(h.period_ns) + " ns out of range");
    if ((size - sizeof h) / sizeof(RecordedInput) != h.records ||
        (size - sizeof h) % sizeof(RecordedInput) != 0)
        return fail("header says " + std::to_string(h.records) + " records, the file holds " +
                    std::to_string((size - sizeof h) / sizeof(RecordedInput)));
    out.version = h.version;
    out.period_ns = h.period_ns;
    out.inputs.resize(h.records);
    if (h.records &&
        std::fread(out.inputs.data(), sizeof(RecordedInput), h.records, f) != h.records)
        return fail("short read");
    std::fclose(f);
    std::uint64_t generation = 0, device_generation = 0;
    for (std::uint64_t i = 0; i < h.records; ++i) {
        const RecordedInput& r = out.inputs[i];
        const std::string at = "record " + std::to_string(i) + ": ";
        if (r.tick != i)
            return Err{"recording " + path + ": " + at + "tick " + std::to_string(r.tick)};
        if (r.status > std::uint8_t(DeviceStatus::kError))
            return Err{"recording " + path + ": " + at + "bad status " + std::to_string(r.status)};
        if (h.version == 1 && (r.overran_last || r.missed_deadlines))
            return Err{"recording " + path + ": " + at + "version 1 with timing fields set"};
        if (h.version < 3 && r.device_generation)
            return Err{"recording " + path + ": " + at + "version " + std::to_string(h.version) +
                       " with a device generation"};
        if (r.device_generation < device_generation || r.device_generation > device_generation + 1)
            return Err{"recording " + path + ": " + at + "device generation " +
                       std::to_string(r.device_generation) + " after " +
                       std::to_string(device_generation) + " (one re-open a tick at most)"};
        device_generation = r.device_generation;
        if (r.overran_last > 1 || r.missed_deadlines > kMaxMissed)
            return Err{"recording " + path + ": " + at + "bad timing (overran " +
                       std::to_string(r.overran_last) + ", missed deadlines " +
                       std::to_string(r.missed_deadlines) + ")"};
        if (!finite(r.position_m, 3) || !finite(r.velocity_m_per_s, 3) ||
            !finite(r.orientation_wxyz, 4))
            return Err{"recording " + path + ": " + at + "non-finite sample"};
        if (r.world_generation < generation)
            return Err{"recording " + path + ": " + at + "world generation goes backwards"};
        generation = r.world_generation;
    }
    return out;
}

ReplayDevice::ReplayDevice(const Recording& recording, ReplayWorldGate gate) noexcept
    : recording_(recording), gate_(gate) {}

std::uint64_t ReplayDevice::device_generation_due() const noexcept {
    const std::vector<RecordedInput>& in = recording_.inputs;
    if (in.empty()) return 0;
    return in[next_ < in.size() ? next_ : in.size() - 1].device_generation;
}

RecordedTiming ReplayDevice::recorded_timing() const noexcept {
    if (next_ == 0 || next_ > recording_.inputs.size()) return {};
    const RecordedInput& r = recording_.inputs[next_ - 1];
    return {r.missed_deadlines, r.overran_last != 0};
}

DeviceStatus ReplayDevice::try_read(DeviceSample& out, std::uint32_t) noexcept {
    const std::vector<RecordedInput>& in = recording_.inputs;
    if (next_ >= in.size()) return DeviceStatus::kDisconnected;
    const RecordedInput& r = in[next_++];
    // The world the next tick swaps in must be offered now, and nothing newer (the builder's gate).
    if (next_ < in.size() && gate_.release && gate_.offered) {
        const std::uint64_t due = in[next_].world_generation;
        gate_.release->store(due, std::memory_order_release);
        const auto limit =
            std::chrono::steady_clock::now() + std::chrono::milliseconds(gate_.wait_limit_ms);
        while (due > given_up_generation_ && gate_.offered->load(std::memory_order_acquire) < due) {
            if (gate_.stop && gate_.stop->load(std::memory_order_acquire)) break;  // stopping
            if (std::chrono::steady_clock::now() > limit) {
                ++late_worlds_;
                given_up_generation_ = due;  // counted once; the replay goes on without it
                break;
            }
            if (gate_.keep_alive) gate_.keep_alive(gate_.keep_alive_context);
            std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
    }
    const auto status = DeviceStatus(r.status);
    if (status != DeviceStatus::kOk) ++counters_.timeouts;
    // Version 3 records the loop's sample after every read; earlier versions only kOk samples.
    if (status != DeviceStatus::kOk && recording_.version < 3) return status;
    out.count = r.sample_count;
    out.device_sequence = r.device_sequence;
    out.buttons = r.buttons;
    for (int i = 0; i < 3; ++i) {
        out.position_m[i] = r.position_m[i];
        out.velocity_m_per_s[i] = r.velocity_m_per_s[i];
    }
    for (int i = 0; i < 4; ++i) out.orientation_wxyz[i] = r.orientation_wxyz[i];
    out.command_lag = r.command_lag;
    out.flags = flags_from(r.flags);
    out.has_orientation = r.has_orientation != 0;
    if (status == DeviceStatus::kOk) ++counters_.samples;
    return status;
}

}  // namespace kerf::rt
