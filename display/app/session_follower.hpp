// kerf::display::SessionFollower — kerf-display's cutting side, on a worker thread of its own, so
// that frames never wait for a cut:
//
//   attach to the session as a consumer (retrying until kerf-rt runs) ── catch up from the
//   journal ── follow the ring ── apply each event to the CutSession ── after each batch of
//   edits: hand the changes to the frame side (EditSink, on this thread, under the caller's
//   lock), publish the collision mesh through the mailbox ── idle: grow cutting capacity.
//
// Restartable: it always starts from sequence 0 (the journal), so a display started at any time,
// or restarted after kill -9, applies the same events in the same order as one that never died,
// and reaches the same CutSession::hash(). A new session (another session id, or SessionReset)
// rebuilds the CutSession from the scene. Garbage in the segment is the Consumer's to reject
// and count; nothing read from shared memory reaches the session unvalidated.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "config/base/result.hpp"
#include "display/cut/cut_session.hpp"
#include "rt_core/ipc/consumer.hpp"

namespace kerf::display {

/// Builds the scene's mesh (world frame): at start, on a new session and on SessionReset.
using SceneLoader = std::function<Result<mesh::TriMesh, std::string>()>;

/// Called on the worker after each batch of edits (`changes` since the previous call; the first
/// call reports everything). `newest_event_ns` is the CLOCK_MONOTONIC stamp of the newest event
/// in the batch (0 for a rebuild). Keep it short: copy what the frame side needs, under a lock.
using EditSink =
    std::function<void(const cut::CutSession& session, const cut::SessionChanges& changes,
                       std::uint64_t newest_event_ns)>;

struct FollowerOptions {
    std::string segment_name;       ///< the session segment (kerf.toml [shm] session_name)
    bool publish_collision = true;  ///< publish the collision mesh after edits
    std::uint64_t stale_after_ns = 200'000'000;  ///< producer heartbeat limit when attaching
    std::uint32_t poll_period_us = 1000;  ///< sleep when there is nothing to do (never spins)
    /// Take CutSession::hash() (O(mesh) on the worker, so it would slow the frames sharing its
    /// core) once this many events are applied and the follower is idle; 0: never.
    std::uint64_t hash_at_sequence = 0;
};

/// A copy of the follower's counters (status() takes it under a lock).
struct FollowerStatus {
    bool attached = false;
    std::string waiting_for;             ///< why not attached yet ("" when attached)
    std::uint64_t session_id = 0;        ///< segment's session id (0 before attaching)
    std::uint64_t next_sequence = 0;     ///< events applied so far (= next expected sequence)
    cut::SessionCounters session;        ///< applied / refused / ignored / cuts / growth
    ipc::ConsumerStats consumer;         ///< delivered, from journal, gaps, lost, rejections
    std::uint64_t publishes = 0;         ///< collision meshes published
    std::uint64_t publish_failures = 0;  ///< refused by export or the mailbox (last_error says)
    std::int64_t last_publish_ns = 0;    ///< worker time of the last export + publish
    std::string last_error;
    std::uint32_t bodies = 0;
    bool cut_open = false;
    /// Feed depth of the open (or the last) cut as kerf-rt reported it in its newest cut
    /// event, m; -1 before any cut of this session.
    double cut_depth_m = -1;
    std::int64_t last_batch_ns = 0;   ///< worker time of the last batch of edits
    std::vector<double> edit_ms;      ///< worker time of each batch of edits (first 256), ms
    std::uint64_t hash = 0;           ///< CutSession::hash() at `hash_sequence`
    std::uint64_t hash_sequence = 0;  ///< next_sequence when `hash` was taken
    bool hash_valid = false;
    std::uint64_t backlog = 0;  ///< events the producer published that are not applied yet
    ipc::LatestState state{};   ///< the latest tool pose / loop health (if state_valid)
    bool state_valid = false;
};

class SessionFollower {
public:
    /// Loads the scene (fails with its message), then starts the worker thread.
    static Result<std::unique_ptr<SessionFollower>, std::string> start(FollowerOptions options,
                                                                       SceneLoader load_scene,
                                                                       EditSink sink);
    ~SessionFollower();  ///< stops the worker (it releases the consumer slot)

    /// The counters now (thread-safe).
    FollowerStatus status() const;
    /// Stops the worker; the session is left as it is. Idempotent.
    void stop();

private:
    struct Impl;
    explicit SessionFollower(std::unique_ptr<Impl> impl) noexcept;
    std::unique_ptr<Impl> impl_;
};

}  // namespace kerf::display
