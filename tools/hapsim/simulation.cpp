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
    if (trace_on_)
        trace_.push_back(
            {steps_, model_.position_m(), hand_.position_m(), model_.applied_force_n()});
}

bool Simulation::write_trace(const std::filesystem::path& path, std::string& why) const {
    std::FILE* f = std::fopen(path.c_str(), "w");
    if (f == nullptr) {
        why = "cannot write trace " + path.string() + ": " + std::strerror(errno);
        return false;
    }
    std::fprintf(f, "step,x_m,y_m,z_m,hand_x_m,hand_y_m,hand_z_m,fx_n,fy_n,fz_n\n");
    for (const auto& r : trace_) {
        std::fprintf(f, "%llu,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.6f,%.6f,%.6f\n",
                     static_cast<unsigned long long>(r.step), r.position_m[0], r.position_m[1],
                     r.position_m[2], r.hand_m[0], r.hand_m[1], r.hand_m[2], r.motor_force_n[0],
                     r.motor_force_n[1], r.motor_force_n[2]);
    }
    return std::fclose(f) == 0;
}

}  // namespace kerf::hapsim
