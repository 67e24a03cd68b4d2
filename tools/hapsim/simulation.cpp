#include "tools/hapsim/simulation.hpp"

#include <cstdio>
#include <cstring>

#include "tools/hapsim/emulated_device.hpp"

namespace kerf::hapsim {

void Outbox::push(std::byte tag, std::span<const std::byte> payload) {
    std::vector<std::byte> d(payload.size() + 1);
    d[0] = tag;
    if (!payload.empty()) std::memcpy(d.data() + 1, payload.data(), payload.size());
    datagrams.push_back(std::move(d));
}

Simulation::Simulation(const ModelParams& params, HandScript script, const Vec3& start_m,
                       double period_s)
    : model_(params), hand_(std::move(script), start_m), period_s_(period_s) {
    model_.reset(start_m);
}

void Simulation::step(const Vec3& motor_force_n) {
    ++steps_;
    events_.clear();
    hand_.advance(time_s(), events_);
    for (const auto& e : events_) {
        const auto why = apply_fault(faults_, e.name, e.value);
        if (!why.empty()) warnings_.push_back("script fault ignored: " + why);
    }
    model_.step(period_s_, motor_force_n, hand_.position_m(), hand_.velocity_m_per_s());
    if (trace_ != nullptr)
        write_trace_row(
            {steps_, model_.position_m(), hand_.position_m(), model_.applied_force_n()});
}

Simulation::~Simulation() {
    std::string ignored;
    close_trace(ignored);
}

bool Simulation::open_trace(const std::filesystem::path& path, std::uint64_t max_bytes,
                            std::string& why) {
    trace_ = std::fopen(path.c_str(), "we");
    if (trace_ == nullptr) {
        why = "cannot write trace " + path.string() + ": " + std::strerror(errno);
        return false;
    }
    trace_path_ = path;
    trace_max_bytes_ = max_bytes;
    const int n =
        std::fprintf(trace_, "step,x_m,y_m,z_m,hand_x_m,hand_y_m,hand_z_m,fx_n,fy_n,fz_n\n");
    trace_bytes_ = n > 0 ? std::uint64_t(n) : 0;
    if (n < 0 || std::fflush(trace_) != 0) {
        why = "cannot write trace " + path.string() + ": " + std::strerror(errno);
        std::fclose(trace_);
        trace_ = nullptr;
        return false;
    }
    return true;
}

void Simulation::write_trace_row(const TraceRow& r) {
    if (trace_full_ || trace_failed_) return;
    if (trace_bytes_ >= trace_max_bytes_) {
        trace_full_ = true;
        return;
    }
    const int n =
        std::fprintf(trace_, "%llu,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.6f,%.6f,%.6f\n",
                     static_cast<unsigned long long>(r.step), r.position_m[0], r.position_m[1],
                     r.position_m[2], r.hand_m[0], r.hand_m[1], r.hand_m[2], r.motor_force_n[0],
                     r.motor_force_n[1], r.motor_force_n[2]);
    if (n < 0) {
        trace_failed_ = true;
        return;
    }
    trace_bytes_ += std::uint64_t(n);
}

bool Simulation::close_trace(std::string& why) {
    if (trace_ == nullptr) return true;
    const bool closed = std::fclose(trace_) == 0;
    trace_ = nullptr;
    if (trace_failed_ || !closed) {
        why = "trace " + trace_path_.string() + ": write failed (disk full?)";
        return false;
    }
    if (trace_full_) {
        why = "trace " + trace_path_.string() + ": stopped at its " +
              std::to_string(trace_max_bytes_) + "-byte limit (--trace-max-mb)";
        return false;
    }
    return true;
}

}  // namespace kerf::hapsim
