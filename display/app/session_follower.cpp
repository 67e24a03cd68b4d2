#include "display/app/session_follower.hpp"

#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <optional>
#include <thread>

#include "display/app/collision_export.hpp"
#include "display/app/session_events_ipc.hpp"
#include "rt_core/ipc/mesh_mailbox.hpp"

namespace kerf::display {
namespace {

using Clock = std::chrono::steady_clock;

constexpr auto kBatchTime = std::chrono::milliseconds(20);     // apply at most this long per batch
constexpr auto kAttachRetry = std::chrono::milliseconds(100);  // between attach attempts
constexpr auto kHashPeriod =
    std::chrono::milliseconds(100);  // idle hash refresh at most this often

}  // namespace

struct SessionFollower::Impl {
    FollowerOptions options;
    SceneLoader load_scene;
    EditSink sink;
    std::optional<cut::CutSession> session;
    std::optional<ipc::Consumer> consumer;
    std::unique_ptr<ipc::CollisionMesh> collision;  // ~38 MB (mailbox capacity), allocated once
    cut::SessionChanges changes;
    std::uint64_t session_id = 0;
    Clock::time_point last_hash{};
    bool publish_pending = false;  // an edit not yet published (no consumer at the time)

    mutable std::mutex status_mutex;
    FollowerStatus shared;  // guarded by status_mutex
    FollowerStatus local;   // the worker's copy, published to `shared` after each step

    std::atomic<bool> stop_requested{false};
    std::thread worker;

    void run();
    bool try_attach();
    bool rebuild_session();
    std::uint64_t apply_batch(bool& reset);
    void hand_over(std::uint64_t newest_event_ns);
    void publish_if_owed();
    void publish();
    void publish_status();
};

bool SessionFollower::Impl::rebuild_session() {
    auto scene = load_scene();
    if (!scene) {
        local.last_error = "scene: " + scene.error();
        spdlog::error("kerf-display: cannot rebuild the scene: {}", scene.error());
        return false;
    }
    session.reset();
    session.emplace(std::move(*scene));
    local.cut_depth_m = -1;
    return true;
}

bool SessionFollower::Impl::try_attach() {
    auto attached =
        ipc::ConsumerBuilder()
            .segment_name(options.segment_name)
            .from_sequence(0)
            .stale_after_ns(options.stale_after_ns)
            .role(ipc::ConsumerRole::kDisplay)  // the reserved slot: tools cannot take it
            .attach();
    if (!attached) {
        local.waiting_for = attached.error().message();
        return false;
    }
    consumer.emplace(std::move(*attached));
    const std::uint64_t id = consumer->layout().header.session_id;
    if (id != session_id && session_id != 0 && !rebuild_session()) return false;
    session_id = id;
    local.attached = true;
    local.waiting_for.clear();
    local.session_id = id;
    spdlog::info("kerf-display: attached to {} (slot {}, session {:016x})", options.segment_name,
                 consumer->slot(), id);
    publish_if_owed();
    return true;
}

std::uint64_t SessionFollower::Impl::apply_batch(bool& reset) {
    std::uint64_t newest_ns = 0;
    const auto until = Clock::now() + kBatchTime;
    ipc::EventRecord record;
    while (!stop_requested.load(std::memory_order_relaxed) && Clock::now() < until &&
           consumer->try_next(record) == ipc::Poll::kEvent) {
        const RecordOutcome out = apply_record(*session, record);
        if (out.topology) local.cut_depth_m = record.cut.feed_depth_m;  // validated, finite
        if (out.report.outcome == cut::EventOutcome::kRefused) {
            spdlog::warn("kerf-display: event {} ({}) refused: {} {}", record.header.sequence,
                         ipc::to_string(record.header.type), out.report.why,
                         cut::to_string(out.report.status));
        }
        if (out.session_reset) {
            reset = true;
            rebuild_session();
        }
        newest_ns = record.header.time_ns;
    }
    return newest_ns;
}

void SessionFollower::Impl::hand_over(std::uint64_t newest_event_ns) {
    session->take_changes(changes);
    if (sink) sink(*session, changes, newest_event_ns);
    const bool geometry =
        changes.everything || changes.bodies || !changes.vertices.empty() || !changes.faces.empty();
    publish_pending = publish_pending || (geometry && options.publish_collision);
}

void SessionFollower::Impl::publish_if_owed() {
    // Not while a cut is open: kerf-rt's saw owns the blade's own kerf until CutEnd; a partly
    // opened kerf swapped into its world mid-cut made it end the cut early and begin another.
    // Checked after every step, not only after edits: a batch that only closed the cut (a
    // withdrawn CutEnd changes no geometry) still owes kerf-rt the mesh held back meanwhile
    // (lockstep and replay wait for it; a live kerf-rt would run on in the pre-cut world).
    if (publish_pending && consumer && !session->cut_open()) publish();
}

void SessionFollower::Impl::publish() {
    publish_pending = false;
    const auto t0 = Clock::now();
    if (auto ok = export_collision(*session, *collision); !ok) {
        ++local.publish_failures;
        local.last_error = "collision mesh not published: " + ok.error();
        return;
    }
    ipc::MeshMailboxWriter writer(consumer->writable_layout());
    const auto published = writer.publish(*collision);
    if (!published) {
        ++local.publish_failures;
        local.last_error = "collision mesh refused: " + published.error().message();
        return;
    }
    ++local.publishes;
    local.last_publish_ns =
        std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t0).count();
    spdlog::info(
        "kerf-display: collision mesh generation {} published ({} bodies, {} vertices, {} "
        "triangles; export + publish {:.1f} ms)",
        *published, collision->body_count, collision->vertex_count, collision->index_count / 3,
        double(local.last_publish_ns) * 1e-6);
}

void SessionFollower::Impl::publish_status() {
    local.session = session->counters();
    local.bodies = static_cast<std::uint32_t>(session->bodies().size());
    local.cut_open = session->cut_open();
    if (consumer) {
        local.consumer = consumer->stats();
        local.next_sequence = consumer->next_sequence();
        const std::uint64_t published =
            consumer->layout().producer.next_event_sequence.load(std::memory_order_acquire);
        local.backlog = published > local.next_sequence ? published - local.next_sequence : 0;
        ipc::LatestState state;
        if (consumer->try_read_state(state) == ipc::SeqlockRead::kOk) {
            local.state = state;
            local.state_valid = true;
        }
    }
    const std::lock_guard lock(status_mutex);
    shared = local;
}

void SessionFollower::Impl::run() {
    hand_over(0);  // the scene as loaded: everything
    publish_status();
    while (!stop_requested.load(std::memory_order_relaxed)) {
        if (!consumer && !try_attach()) {
            publish_status();
            std::this_thread::sleep_for(kAttachRetry);
            continue;
        }
        const auto t0 = Clock::now();
        bool reset = false;
        const std::uint64_t newest_ns = apply_batch(reset);
        if (session->has_changes()) {
            hand_over(newest_ns);
            publish_if_owed();  // inside the batch's time, as the edit it follows
            local.last_batch_ns =
                std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t0).count();
            if (newest_ns != 0 && local.edit_ms.size() < 256)
                local.edit_ms.push_back(double(local.last_batch_ns) * 1e-6);
        } else {
            publish_if_owed();
        }
        const bool busy = newest_ns != 0 || reset;
        if (!busy) {
            const std::uint64_t applied = consumer->next_sequence();
            const bool hash_wanted = options.hash_at_sequence != 0 &&
                                     applied >= options.hash_at_sequence &&
                                     (!local.hash_valid || local.hash_sequence != applied);
            if (hash_wanted && Clock::now() - last_hash >= kHashPeriod) {
                local.hash = session->hash();
                local.hash_sequence = consumer->next_sequence();
                local.hash_valid = true;
                last_hash = Clock::now();
            } else if (!session->idle()) {
                const auto health = consumer->producer_health();
                if (health == ipc::ProducerHealth::kDead) {  // kerf-rt gone: wait for the next
                    spdlog::warn("kerf-display: producer of {} is gone; waiting for a new session",
                                 options.segment_name);
                    consumer.reset();
                    local.attached = false;
                }
                std::this_thread::sleep_for(std::chrono::microseconds(options.poll_period_us));
            }
        }
        publish_status();
    }
}

Result<std::unique_ptr<SessionFollower>, std::string> SessionFollower::start(
    FollowerOptions options, SceneLoader load_scene, EditSink sink) {
    auto impl = std::make_unique<Impl>();
    impl->options = std::move(options);
    impl->load_scene = std::move(load_scene);
    impl->sink = std::move(sink);
    impl->collision = std::make_unique<ipc::CollisionMesh>();
    if (!impl->rebuild_session()) return Err{impl->local.last_error};
    impl->local.waiting_for = "not attached yet";
    Impl* raw = impl.get();
    impl->worker = std::thread([raw] { raw->run(); });
    return std::unique_ptr<SessionFollower>(new SessionFollower(std::move(impl)));
}

SessionFollower::SessionFollower(std::unique_ptr<Impl> impl) noexcept : impl_(std::move(impl)) {}

SessionFollower::~SessionFollower() { stop(); }

void SessionFollower::stop() {
    impl_->stop_requested.store(true, std::memory_order_relaxed);
    if (impl_->worker.joinable()) impl_->worker.join();
}

FollowerStatus SessionFollower::status() const {
    const std::lock_guard lock(impl_->status_mutex);
    return impl_->shared;
}

}  // namespace kerf::display
