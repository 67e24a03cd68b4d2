// Device-layer speed: codec encode/decode per packet, and the host <-> kerf-hapsim round trip
// over the Unix socket (write one command, read its reply) against the floor — a bare
// SOCK_SEQPACKET socketpair ping-pong with a forked echo process — measured in the same run.
// Run by hand:  build/bin/bench_device --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstring>
#include <vector>

#include "config/base/main_guard.hpp"
#include "firmware_host/device/falcon_device.hpp"
#include "firmware_host/device/kerf_hid_device.hpp"
#include "firmware_host/falcon/delta_kinematics.hpp"
#include "firmware_host/falcon/falcon_packet.hpp"
#include "firmware_host/protocol/crc16.hpp"
#include "firmware_host/protocol/kerf_hid_codec.hpp"
#include "firmware_host/transport/socket_report_transport.hpp"
#include "firmware_host/transport/socket_usb_link.hpp"
#include "tests/firmware_host/hapsim_process.hpp"

namespace fh = kerf::firmware_host;
using Clock = std::chrono::steady_clock;

namespace {

fh::InputReport sample_input() {
    fh::InputReport in;
    in.sequence = 42;
    in.status = fh::kStatusHomed | fh::kStatusAmplifiersOn;
    in.position = {12345, -23456, 34567};
    return in;
}

// Reference for the Kerf codec figures: the CRC every checked report needs anyway.
void BM_Crc16Over62Bytes(benchmark::State& state) {
    std::array<std::byte, fh::kReportSize> a{};
    for (auto _ : state) {
        benchmark::DoNotOptimize(a.data());
        benchmark::DoNotOptimize(fh::crc16_ccitt(std::span<const std::byte>(a.data(), 62)));
    }
}
BENCHMARK(BM_Crc16Over62Bytes);

void BM_KerfEncodeInput(benchmark::State& state) {
    std::array<std::byte, fh::kReportSize> buf{};
    auto in = sample_input();
    for (auto _ : state) {
        ++in.sequence;
        benchmark::DoNotOptimize(fh::encode_input(in, buf));
        benchmark::ClobberMemory();
    }
}
BENCHMARK(BM_KerfEncodeInput);

void BM_KerfDecodeInput(benchmark::State& state) {
    std::array<std::byte, fh::kReportSize> buf{};
    (void)fh::encode_input(sample_input(), buf);
    fh::InputReport out;
    for (auto _ : state) {
        benchmark::DoNotOptimize(fh::decode_input(buf, out));
        benchmark::ClobberMemory();
    }
}
BENCHMARK(BM_KerfDecodeInput);

void BM_FalconEncodeCommand(benchmark::State& state) {
    std::array<std::byte, fh::falcon::kPacketSize> buf{};
    fh::falcon::FalconCommand cmd{{1000, -2000, 3000}, 1, false};
    for (auto _ : state) {
        ++cmd.motor[0];
        benchmark::DoNotOptimize(fh::falcon::encode_command(cmd, buf));
        benchmark::ClobberMemory();
    }
}
BENCHMARK(BM_FalconEncodeCommand);

void BM_FalconDecodeReport(benchmark::State& state) {
    std::array<std::byte, fh::falcon::kPacketSize> buf{};
    (void)fh::falcon::encode_report({{100, -200, 300}, 7, 1}, buf);
    fh::falcon::FalconReport out;
    for (auto _ : state) {
        benchmark::DoNotOptimize(fh::falcon::decode_report(buf, out));
        benchmark::ClobberMemory();
    }
}
BENCHMARK(BM_FalconDecodeReport);

void BM_FalconForwardKinematics(benchmark::State& state) {
    const fh::falcon::DeltaKinematics kin{fh::falcon::DeltaGeometry{}};
    fh::Vec3 theta{}, p{}, guess = {0, 0, 0.11};
    (void)kin.inverse({0.01, -0.02, 0.11}, theta);
    for (auto _ : state) {
        benchmark::DoNotOptimize(kin.forward(theta, guess, p));
        benchmark::ClobberMemory();
    }
}
BENCHMARK(BM_FalconForwardKinematics);

void report_percentiles(benchmark::State& state, std::vector<double>& us) {
    if (us.empty()) return;
    std::sort(us.begin(), us.end());
    state.counters["p50_us"] = us[us.size() / 2];
    state.counters["p99_us"] = us[us.size() * 99 / 100];
}

// The floor: one 65-byte datagram to a forked echo process and back.
void BM_SocketpairPingPongFloor(benchmark::State& state) {
    auto pair = fh::seqpacket_pair();
    if (!pair) {
        state.SkipWithError(pair.error().message().c_str());
        return;
    }
    const pid_t child = ::fork();
    if (child == 0) {
        std::array<std::byte, 128> b{};
        for (;;) {
            std::size_t n = 0;
            if (pair->second.receive(b, n, 1000000) != fh::LinkStatus::kOk) ::_exit(0);
            (void)pair->second.try_send(std::span(b).first(n));
        }
    }
    pair->second.close();
    std::array<std::byte, 65> msg{};
    std::array<std::byte, 128> reply{};
    std::vector<double> us;
    us.reserve(1 << 20);
    for (auto _ : state) {
        const auto t0 = Clock::now();
        (void)pair->first.try_send(msg);
        std::size_t n = 0;
        (void)pair->first.receive(reply, n, 100000);
        us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
    }
    pair->first.close();
    ::waitpid(child, nullptr, 0);
    report_percentiles(state, us);
}
BENCHMARK(BM_SocketpairPingPongFloor)->UseRealTime();

// One tick against kerf-hapsim (lockstep): encode + send a command, receive + decode its reply.
template <class Open>
void hapsim_round_trip(benchmark::State& state, std::vector<std::string> args, Open open) {
    kerf::firmware_host::test::HapsimProcess sim(std::move(args));
    if (!sim.ready()) {
        state.SkipWithError("kerf-hapsim did not start");
        return;
    }
    auto socket = fh::SeqpacketSocket::connect(sim.socket_path());
    if (!socket) {
        state.SkipWithError(socket.error().message().c_str());
        return;
    }
    auto dev = open(std::move(*socket));
    if (!dev) {
        state.SkipWithError("open failed");
        return;
    }
    fh::DeviceSample sample;
    std::vector<double> us;
    us.reserve(1 << 20);
    for (auto _ : state) {
        const auto t0 = Clock::now();
        (void)dev->try_write(fh::DeviceCommand{});
        const auto s = dev->try_read(sample, 100000);
        us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
        if (s != fh::DeviceStatus::kOk) {
            state.SkipWithError("round trip failed");
            break;
        }
    }
    report_percentiles(state, us);
}

void BM_HapsimRoundTripKerfHid(benchmark::State& state) {
    hapsim_round_trip(state, {"--protocol", "kerf"},
                      [](fh::SeqpacketSocket s) -> std::unique_ptr<fh::Device> {
                          auto d = fh::KerfHidDevice::open(
                              std::make_unique<fh::SocketReportTransport>(std::move(s)), {});
                          return d ? std::unique_ptr<fh::Device>(std::move(*d)) : nullptr;
                      });
}
BENCHMARK(BM_HapsimRoundTripKerfHid)->UseRealTime();

void BM_HapsimRoundTripFalcon(benchmark::State& state) {
    hapsim_round_trip(state, {"--protocol", "falcon", "--firmware-loaded"},
                      [](fh::SeqpacketSocket s) -> std::unique_ptr<fh::Device> {
                          auto d = fh::FalconDevice::open(
                              std::make_unique<fh::SocketUsbLink>(std::move(s)), {});
                          return d ? std::unique_ptr<fh::Device>(std::move(*d)) : nullptr;
                      });
}
BENCHMARK(BM_HapsimRoundTripFalcon)->UseRealTime();

}  // namespace

// Google Benchmark's main, with nothing escaping: an exception is a message and exit 1.
int main(int argc, char** argv) {
    return kerf::guarded_main("bench_device", [&] {
        benchmark::Initialize(&argc, argv);
        if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
        benchmark::RunSpecifiedBenchmarks();
        benchmark::Shutdown();
        return 0;
    });
}
