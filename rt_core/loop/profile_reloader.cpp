#include "rt_core/loop/profile_reloader.hpp"

#include <poll.h>
#include <spdlog/spdlog.h>
#include <sys/inotify.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "firmware_host/open/open_device.hpp"
#include "rt_core/physics/physics_params_from_profile.hpp"

namespace kerf::rt {

ProfileReloader::ProfileReloader(Handoff<ProfileUpdate>& handoff, std::filesystem::path file,
                                 config::ForceProfile current, config::DeviceProfile device,
                                 double period_s, physics::PhysicsParams base)
    : handoff_(handoff),
      file_(std::move(file)),
      committed_(current),
      offered_(std::move(current)),
      device_(std::move(device)),
      period_s_(period_s),
      base_(base) {}

ProfileReloader::~ProfileReloader() {
    stop();
    if (inotify_fd_ >= 0) close(inotify_fd_);
}

bool ProfileReloader::start() {
    inotify_fd_ = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
    if (inotify_fd_ >= 0) {
        const auto dir = file_.has_parent_path() ? file_.parent_path() : ".";
        if (inotify_add_watch(inotify_fd_, dir.c_str(), IN_CLOSE_WRITE | IN_MOVED_TO) < 0) {
            last_error_ = "inotify watch on " + dir.string() + ": " + std::strerror(errno);
            close(inotify_fd_);
            inotify_fd_ = -1;
        }
    } else {
        last_error_ = std::string("inotify: ") + std::strerror(errno);
    }
    stop_.store(false, std::memory_order_release);
    thread_ = std::thread([this] { run(); });
    return inotify_fd_ >= 0;
}

void ProfileReloader::stop() {
    stop_.store(true, std::memory_order_release);
    if (thread_.joinable()) thread_.join();
}

void ProfileReloader::run() {
    alignas(inotify_event) char buffer[4096];
    while (!stop_.load(std::memory_order_acquire)) {
        pollfd p{inotify_fd_, POLLIN, 0};
        const int ready = inotify_fd_ >= 0 ? poll(&p, 1, 50) : (usleep(50'000), 0);
        bool changed = false;
        if (ready > 0) {
            ssize_t n;
            while ((n = read(inotify_fd_, buffer, sizeof buffer)) > 0) {
                for (ssize_t off = 0; off < n;) {
                    const auto* ev = reinterpret_cast<const inotify_event*>(buffer + off);
                    if (ev->len > 0 && file_.filename() == ev->name) changed = true;
                    off += ssize_t(sizeof(inotify_event) + ev->len);
                }
            }
        }
        if (requested_.exchange(false, std::memory_order_acq_rel)) changed = true;
        if (changed) reload_now();
        handoff_.collect();
    }
}

bool ProfileReloader::reload_now() {
    auto loaded = config::load_force_profile(file_);
    std::string error;
    if (!loaded) {
        error = loaded.error().message();
    } else if (loaded->limits.max_force_n > device_.limits.peak_force_n) {
        error = file_.string() + ": limits.max_force_n " +
                std::to_string(loaded->limits.max_force_n) + " exceeds the device's peak_force_n " +
                std::to_string(device_.limits.peak_force_n);
    }
    if (!error.empty()) {
        last_error_ = error;
        refused_.fetch_add(1, std::memory_order_acq_rel);
        spdlog::error("kerf-rt: force profile refused, the running profile stays: {}", error);
        return false;
    }
    // An offer the loop has not taken yet is taken back: its changes are diffed again from
    // the profile the loop really has, so no ParametersChanged is lost when reloads come faster
    // than ticks.
    if (!handoff_.reclaim()) committed_ = offered_;
    auto update = std::make_unique<ProfileUpdate>();
    update->change_count = diff_profiles(committed_, *loaded, update->changes);
    offered_ = *loaded;
    if (update->change_count == 0) return false;  // touched, not changed
    update->revision = accepted_.load(std::memory_order_acquire) + 1;
    update->physics = physics::physics_params_from_profile(*loaded, base_);
    update->safety = firmware_host::safety_limits_from(device_, &*loaded, period_s_);
    spdlog::info("kerf-rt: force profile {} reloaded: {} values changed", file_.string(),
                 update->change_count);
    handoff_.offer(std::move(update));
    accepted_.fetch_add(1, std::memory_order_acq_rel);
    return true;
}

}  // namespace kerf::rt
