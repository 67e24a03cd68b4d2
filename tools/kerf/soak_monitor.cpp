#include "tools/kerf/soak_monitor.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

namespace kerf::cli {

Result<std::unique_ptr<SessionMonitor>, std::string> SessionMonitor::start(
    const std::string& session) {
    auto consumer = ipc::ConsumerBuilder()
                        .segment_name(session)
                        .from_sequence(0)
                        .telemetry(true)
                        .role(ipc::ConsumerRole::kMonitor)
                        .stale_after_ns(2'000'000'000)  // a loaded machine stalls kerf-rt
                        .attach();
    if (!consumer) return Err{"monitor: " + consumer.error().message()};
    std::unique_ptr<SessionMonitor> m(new SessionMonitor(std::move(*consumer)));
    m->data_.ticks.reserve(1 << 16);
    m->thread_ = std::thread([p = m.get()] { p->run(); });
    return m;
}

SessionMonitor::SessionMonitor(ipc::Consumer consumer) : consumer_(std::move(consumer)) {}

SessionMonitor::~SessionMonitor() { stop(); }

std::uint64_t SessionMonitor::published_events() const noexcept {
    return consumer_.layout().producer.next_event_sequence.load(std::memory_order_acquire);
}

void SessionMonitor::run() {
    ipc::EventRecord event{};
    ipc::TelemetrySample sample{};
    std::vector<TickSample> ticks;
    std::vector<SeenEvent> events;
    while (!stop_.load(std::memory_order_relaxed)) {
        ticks.clear();
        events.clear();
        while (consumer_.try_next_telemetry(sample) == ipc::Poll::kEvent) {
            TickSample t;
            t.time_ns = sample.header.time_ns;
            t.tick = sample.header.sequence;
            t.force_n = std::sqrt(sample.force_n[0] * sample.force_n[0] +
                                  sample.force_n[1] * sample.force_n[1] +
                                  sample.force_n[2] * sample.force_n[2]);
            t.penetration_m = sample.penetration_m;
            t.safety_reasons = sample.safety_reasons;
            t.loop_flags = sample.loop_flags;
            t.contact_flags = sample.contact_flags;
            t.period_ns = sample.period_ns;
            ticks.push_back(t);
            contact_.store(t.contact_flags, std::memory_order_relaxed);
            force_.store(t.force_n, std::memory_order_relaxed);
        }
        while (consumer_.try_next(event) == ipc::Poll::kEvent)
            events.push_back({event.header.sequence, event.header.checksum,
                              static_cast<std::uint16_t>(event.header.type)});
        {
            const std::lock_guard lock(mutex_);
            data_.ticks.insert(data_.ticks.end(), ticks.begin(), ticks.end());
            data_.events.insert(data_.events.end(), events.begin(), events.end());
            data_.stats = consumer_.stats();
        }
        if (ticks.empty() && events.empty())
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
}

MonitorData SessionMonitor::stop() {
    if (stopped_) return {};
    stopped_ = true;
    stop_.store(true);
    if (thread_.joinable()) thread_.join();
    // What the journal holds beyond the ring (the producer may have stopped meanwhile).
    ipc::EventRecord event{};
    while (consumer_.try_next(event) == ipc::Poll::kEvent)
        data_.events.push_back({event.header.sequence, event.header.checksum,
                                static_cast<std::uint16_t>(event.header.type)});
    data_.stats = consumer_.stats();
    return std::move(data_);
}

MemorySample read_memory(pid_t pid) {
    MemorySample m;
    std::ifstream f("/proc/" + std::to_string(pid) + "/status");
    std::string line;
    while (std::getline(f, line)) {
        std::istringstream in(line);
        std::string key;
        std::uint64_t kb = 0;
        in >> key >> kb;
        if (key == "VmRSS:") m.rss_kb = kb, m.ok = true;
        if (key == "RssAnon:") m.anon_kb = kb;
        if (key == "RssFile:") m.file_kb = kb;
        if (key == "RssShmem:") m.shmem_kb = kb;
    }
    return m;
}

}  // namespace kerf::cli
