// kerf::physics::SawModel — the running saw in bone: plane lock, feed resistance, cut events.
//
// The blade is an oriented thin box (BladeGeometry) posed by ToolPose: its cutting edge runs along
// u through the tool point, the blade rises from the edge along v, its thickness is along n. While
// the saw runs, the first tick the blade touches bone (the proxy is held by a surface, or the edge
// segment crosses the surface) locks the plane (paper §3.4): point = the edge centre, normal = n,
// in-plane axis = u, and emits CutBegin. While locked:
//  - a spring (plane_lock_stiffness of the material under the edge) pulls the tool back into the
//    plane along the normal; in-plane translation and turning about the normal are free (the
//    twist damping is returned as a torque for devices that render one);
//  - feed resistance opposes advance (motion along -v) through the cut front: the front is a state
//    of its own (its depth along -v), the edge pushes it through a spring (front_stiffness) and it
//    advances at the material's removal rate, force / feed_resistance (the coefficient of the
//    material under the cutting edge: cortical within cortical_thickness_m of a cortical surface
//    triangle, cancellous deeper or near a cut surface). Fed steadily at speed s, the front keeps
//    pace and the force is feed_resistance x s, as a damper on the feed would give; but the front
//    is integrated implicitly, so the force on the device is at most the spring's (front_stiffness
//    x how far the edge is ahead of the front), stable at 1 kHz for any feed_resistance, never
//    pulling (an edge behind the front feels nothing), and the front never goes back. The front
//    is haptic state only: the events' swept region and feed depth follow the edge;
//  - surface contact is off (the blade is in its own kerf): the caller parks the proxy;
//  - CutProgress every progress_period_s or progress_advance_m of new sweep;
//  - CutEnd{kWithdrawn} when the edge comes back above the entry by withdraw_margin_m,
//    CutEnd{kCompleted} when the whole edge has left the bone on the far side (cut through: no
//    surface crossing along the edge and its centre outside),
//    CutEnd{kAborted} when the saw stops or the blade is forced off-plane beyond max_off_plane_m.
// After any CutEnd a new cut can begin only once the blade has been clear of bone for a tick.
// 3-DoF-force devices get the force only; the plane's orientation cannot be held by them.
#pragma once

#include <array>
#include <cstdint>

#include "rt_core/physics/cut_events.hpp"
#include "rt_core/physics/proxy_contact.hpp"

namespace kerf::physics {

/// Resistance of one bone material (config::CuttingMaterial).
struct CuttingParams {
    double feed_resistance_n_s_per_m = 800;      ///< force opposing advance per m/s of feed
    double plane_lock_stiffness_n_per_m = 1500;  ///< spring holding the blade in the plane
    double twist_damping_n_m_s_per_rad = 0.02;   ///< torque opposing turning about the normal
};

struct SawParams {
    BladeGeometry blade;
    CuttingParams cortical;
    CuttingParams cancellous{250, 1000, 0.01};
    double cortical_thickness_m = 0.002;    ///< depth below a cortical surface still cortical
    double front_stiffness_n_per_m = 1500;  ///< spring between the cutting edge and the cut front
    double progress_period_s = 0.005;       ///< CutProgress at least this often while sweeping
    double progress_advance_m = 0.0002;     ///< ... or per this much new sweep
    double withdraw_margin_m = 0.0002;      ///< edge this far above the entry: withdrawn
    double max_off_plane_m = 0.003;         ///< forced further off the plane: aborted
};

/// The tool's pose: the cutting edge centre and the blade axes (columns u, v, n of a rotation).
struct ToolPose {
    Vec3 position_m;   ///< centre of the cutting edge, world frame, m
    Mat3 orientation;  ///< columns: u (edge direction), v (edge -> back), n (blade normal)
};

/// What the saw produced this tick.
struct SawOutput {
    Vec3 force_n;         ///< plane lock + feed resistance on the device, N (locked only)
    Vec3 torque_n_m;      ///< twist damping about the plane normal, N m (locked only)
    bool locked = false;  ///< a cut is in progress after this tick
    Material material = Material::kCortical;  ///< under the cutting edge (locked only)
    double feed_speed_m_s = 0;                ///< cut front's advance speed along -v (>= 0), m/s
    double feed_depth_m = 0;                  ///< edge's deepest advance since first contact, m
    double front_depth_m = 0;                 ///< cut front's depth along -v since first contact, m
    double front_gap_m = 0;  ///< how far the edge is ahead of the cut front (>= 0; the spring), m
    std::array<CutEvent, 2> events{};  ///< events emitted this tick, in order
    std::uint32_t event_count = 0;
};

class SawModel {
public:
    explicit SawModel(const SawParams& params = {}) noexcept : params_(params) {}

    /// New parameters at a tick boundary; a cut in progress keeps its locked plane. noexcept.
    void set_params(const SawParams& params) noexcept { params_ = params; }
    const SawParams& params() const noexcept { return params_; }

    /// One tick. `contact` is this tick's surface contact (ignored while locked); `running` says
    /// whether the saw motor runs. noexcept, no allocation, bounded work.
    SawOutput step(const CollisionWorld& world, const ToolPose& pose, const Vec3& velocity_m_s,
                   double twist_rate_rad_s, bool running, const ContactOutput& contact,
                   double dt_s) noexcept;

    bool locked() const noexcept { return locked_; }
    /// The current cut's begin event (valid while locked()).
    const CutEvent& current_cut() const noexcept { return cut_; }
    /// The cut front's depth along -v from the locked plane point (valid while locked()), m.
    double front_depth_m() const noexcept { return front_depth_m_; }

private:
    Material material_under_edge(const CollisionWorld& world, const Vec3& edge_m) const noexcept;
    bool begin_cut(const CollisionWorld& world, const ToolPose& pose, const ContactOutput& contact,
                   SawOutput& out) noexcept;
    void end_cut(CutEndReason reason, SawOutput& out) noexcept;
    /// Moves the cut front for an edge at `edge_depth_m` this tick; returns the feed force, N.
    double advance_front(double edge_depth_m, double resistance_n_s_per_m, double dt_s) noexcept;
    void emit(CutEventType type, SawOutput& out) noexcept;

    SawParams params_;
    bool locked_ = false;
    std::uint32_t next_cut_id_ = 1;
    CutEvent cut_;                  ///< plane, seed, blade, swept so far
    double front_depth_m_ = 0;      ///< the cut front, along -v from the plane point
    double since_progress_s_ = 0;   ///< time since the last CutProgress
    double reported_extent_m_ = 0;  ///< swept width + height at the last CutProgress
    bool swept_changed_ = false;    ///< the swept region grew since the last CutProgress
    bool been_inside_ = false;      ///< the edge was inside the bone since the lock
    bool armed_ = true;             ///< a touch may start a cut (false until the blade is clear
                                    ///< of bone after a cut ended)
};

}  // namespace kerf::physics
