// kerf::ipc session sockets — how a session's segment reaches its consumers without a name in
// /dev/shm that anyone could truncate. The producer's segment is a sealed memfd (it can neither
// shrink nor grow, so no process can SIGBUS another through it); a non-real-time server thread
// hands its descriptor (and a read-only descriptor of the journal) to each connecting peer over a
// Unix-domain socket with SCM_RIGHTS, after checking the peer's credentials (SO_PEERCRED).
//
//   <runtime dir>/                     default_runtime_dir(): $KERF_RUNTIME_DIR,
//     <name>/                          else $XDG_RUNTIME_DIR/kerf, else /run/kerf (root) or
//       socket                         /tmp/kerf-<uid>; one folder per session, 0700 (0750 for a
//       <session id>.kjournal          kiosk group), socket 0600 (0660); journals stay after exit
#pragma once

#include <sys/types.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "config/base/result.hpp"
#include "rt_core/ipc/ipc_error.hpp"

namespace kerf::ipc {

/// The folder that holds one sub-folder per session (see the file comment for the default order).
std::string default_runtime_dir();

/// Path of session `name`'s folder and socket under `runtime_dir`.
std::string session_dir_of(const std::string& runtime_dir, const std::string& name);
std::string session_socket_of(const std::string& runtime_dir, const std::string& name);

/// Who may attach: the producer's own user, root, and (when `group` >= 0) members of `group`.
struct PeerPolicy {
    uid_t owner_uid = 0;
    gid_t group = 0;
    bool group_allowed = false;
};

/// True if the process `pid` with credentials uid/gid may attach under `policy`.
bool peer_allowed(const PeerPolicy& policy, pid_t pid, uid_t uid, gid_t gid);

/// The producer's side: listens on the session socket from its own (SCHED_OTHER) thread and
/// serves the segment memfd, plus the journal's read-only descriptor once set. Never touches
/// the segment's memory; a peer that connects and stalls cannot block it (one send, then close).
class SessionServer {
public:
    /// Creates the session folder and socket (replacing a stale socket nobody listens on, refusing
    /// a live one) and starts the thread. Takes ownership of `memfd` (closed on failure too).
    static Result<std::unique_ptr<SessionServer>, IpcError> start(const std::string& runtime_dir,
                                                                  const std::string& name,
                                                                  int memfd, PeerPolicy policy,
                                                                  std::uint64_t session_id);
    ~SessionServer();  ///< stops the thread, unlinks the socket, removes the folder if empty

    /// Hands the journal's read-only descriptor to later peers (ownership taken).
    void set_journal_fd(int fd) noexcept;

    const std::string& socket_path() const noexcept { return socket_path_; }
    const std::string& dir_path() const noexcept { return dir_path_; }
    std::uint64_t peers_served() const noexcept { return served_.load(); }
    std::uint64_t peers_refused() const noexcept { return refused_.load(); }

private:
    SessionServer() = default;
    void run() noexcept;
    void serve(int client) noexcept;

    std::string dir_path_, socket_path_;
    int listen_fd_ = -1, memfd_ = -1, wake_[2] = {-1, -1};
    std::atomic<int> journal_fd_{-1};
    PeerPolicy policy_;
    std::uint64_t session_id_ = 0;
    bool bound_ = false;
    std::atomic<std::uint64_t> served_{0}, refused_{0};
    std::thread thread_;
};

/// What a consumer or tool received from a session's producer.
struct SessionFds {
    int segment_fd = -1;  ///< sealed memfd of the segment (read-write)
    int journal_fd = -1;  ///< read-only journal, -1 if the producer has none yet
    pid_t producer_pid = 0;
    uid_t producer_uid = 0;
    gid_t producer_gid = 0;
    std::uint64_t session_id = 0;
};

/// Connects to session `name`'s socket and receives its descriptors (2 s timeout). Errors:
/// kNotFound (no socket), kProducerGone (a stale socket: nobody listens), kUntrusted (folder or
/// socket writable by others, or owned by another user than the producer), kOsError.
Result<SessionFds, IpcError> fetch_session(const std::string& runtime_dir, const std::string& name);

/// A session folder found under the runtime dir: its name and whether a socket is in it.
struct SessionEntry {
    std::string name;
    bool has_socket = false;
};

/// Every session folder under `runtime_dir`, sorted by name (none if the folder does not exist).
std::vector<SessionEntry> list_session_dirs(const std::string& runtime_dir);

/// Removes the socket of a session nobody listens on (connect refused); true if removed.
bool remove_stale_socket(const std::string& runtime_dir, const std::string& name);

}  // namespace kerf::ipc
