// Memory and set-up figures of the cutting context (issue 10, item 10), printed as ratios
// measured in one run: the median of --reps repetitions (5 unless told) with min-max.
//
//   build/bin/bench_cut_setup                          # the 1M-triangle foot
//   build/bin/bench_cut_setup --triangles 200000 --reps 5 --kerf build/bin/kerf [--peer PROG]
//
// Each repetition runs in a fresh process (fork + exec of this program), so resident memory is
// measured from a clean start: the foot is generated once and written as a binary STL (mm) in a
// temporary folder; the child loads it (load_mesh_owned, timed: as `kerf cut` does, no copy of
// the mesh on the way out, room for the context's headroom reserved), returns freed memory to the
// system (malloc_trim), reads its resident size, builds a CutContext (timed) and reads it again,
// then runs the idle steps that write the context's headroom (grow_step until none is due: the
// build only reserves it; timed) and reads it once more. So:
//   context memory / mesh memory   (target <= 0.5; after the idle steps: the steady state)
//   context build / mesh load      (target <= 0.3; also as CPU time, the figure to trust on a
//                                   loaded machine; and with the idle steps added)
// With --kerf, `kerf cut FILE --plane ... --seed ... -o OUT` (a localised cut across the first
// metatarsal, both pieces written) runs as a process, alternating with --peer PROG when given
// (called as `PROG IN.stl px py pz nx ny nz OUT_PREFIX`, e.g. a VTK clip program): wall time
// CPU time (user + system) and peak resident memory (wait4), and their ratios. CPU time is the
// figure to compare on a loaded machine: wall time there includes waiting for a core.
#include <malloc.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "display/cut/cut_context.hpp"
#include "display/mesh/foot_generator.hpp"
#include "display/mesh/mesh_io.hpp"

namespace {

double now_s() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

/// CPU time this process has used (user + system), seconds: on a loaded machine the figure to
/// compare, since wall time also counts waiting for a core.
double cpu_s() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// Resident set size of this process, bytes (/proc/self/statm).
double resident_bytes() {
    std::ifstream f("/proc/self/statm");
    long pages = 0, resident = 0;
    f >> pages >> resident;
    return static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE));
}

struct Spread {
    double median, min, max;
};

Spread spread(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    const double median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
    return {median, v.front(), v.back()};
}

/// One fresh process (`bench_cut_setup --measure FILE FD`, exec'd, so no page of the parent is
/// counted): load, context, idle steps; writes {mesh bytes, context bytes, load s, build s, load
/// cpu s, build cpu s, context bytes after the idle steps, idle steps cpu s} to `fd`.
[[noreturn]] void measure_in_child(const std::filesystem::path& file, int fd) {
    const double rss0 = resident_bytes();
    const double t0 = now_s(), c0 = cpu_s();
    auto mesh = kerf::mesh::load_mesh_owned(file, kerf::LengthUnit::kMillimetre);
    const double t1 = now_s(), c1 = cpu_s();
    if (!mesh) _exit(2);
    malloc_trim(0);
    const double rss1 = resident_bytes();
    const double t2 = now_s(), c2 = cpu_s();
    kerf::cut::CutContext ctx(**mesh);
    const double t3 = now_s(), c3 = cpu_s();
    malloc_trim(0);
    const double rss2 = resident_bytes();
    const double c4 = cpu_s();
    ctx.grow_capacity();
    const double c5 = cpu_s();
    malloc_trim(0);
    const double rss3 = resident_bytes();
    const double out[8] = {rss1 - rss0, rss2 - rss1, t1 - t0,     t3 - t2,
                           c1 - c0,     c3 - c2,     rss3 - rss1, c5 - c4};
    if (write(fd, out, sizeof out) != static_cast<ssize_t>(sizeof out)) _exit(3);
    _exit(0);
}

/// What one process run cost.
struct ProcessCost {
    double wall_s = 0;
    double cpu_s = 0;  ///< user + system: what the run itself used, whatever else loads the machine
    double peak_bytes = 0;
};

double seconds(const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * t.tv_usec; }

/// Runs argv as a process; its cost, or false if it failed.
bool run_process(const std::vector<std::string>& argv, ProcessCost& cost) {
    const double t0 = now_s();
    const pid_t pid = fork();
    if (pid == 0) {
        std::vector<char*> args;
        for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
        args.push_back(nullptr);
        if (std::freopen("/dev/null", "w", stdout) == nullptr) _exit(127);
        execv(args[0], args.data());
        _exit(127);
    }
    int status = 0;
    rusage usage{};
    if (wait4(pid, &status, 0, &usage) != pid) return false;
    cost.wall_s = now_s() - t0;
    cost.cpu_s = seconds(usage.ru_utime) + seconds(usage.ru_stime);
    cost.peak_bytes = static_cast<double>(usage.ru_maxrss) * 1024.0;
    return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

void print_spread(const char* what, const std::vector<double>& v, double scale, const char* unit) {
    const Spread s = spread(v);
    std::printf("  %-44s %10.3f %s  (%.3f-%.3f, n=%zu)\n", what, s.median * scale, unit,
                s.min * scale, s.max * scale, v.size());
}

void print_ratio(const char* what, const std::vector<double>& a, const std::vector<double>& b) {
    const Spread sa = spread(a), sb = spread(b);
    std::printf("  %-44s %10.3f  (%.3f-%.3f)\n", what, sa.median / sb.median, sa.min / sb.max,
                sa.max / sb.min);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc == 4 && std::string(argv[1]) == "--measure")
        measure_in_child(argv[2], std::atoi(argv[3]));
    std::size_t triangles = 1'000'000;
    int reps = 5;
    std::string kerf_exe, peer_exe;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string a = argv[i];
        if (a == "--triangles")
            triangles = std::strtoull(argv[i + 1], nullptr, 10);
        else if (a == "--reps")
            reps = std::max(1, std::atoi(argv[i + 1]));
        else if (a == "--kerf")
            kerf_exe = argv[i + 1];
        else if (a == "--peer")
            peer_exe = argv[i + 1];
        else
            return std::fprintf(stderr, "bench_cut_setup: unknown argument '%s'\n", argv[i]), 2;
    }
    kerf::mesh::FootParams params;
    params.target_triangles = triangles;
    auto foot = kerf::mesh::generate_foot(params);
    if (!foot) return std::fprintf(stderr, "bench_cut_setup: %s\n", foot.error().c_str()), 1;
    char dir_template[] = "/tmp/kerf_bench_cut_setup_XXXXXX";
    if (mkdtemp(dir_template) == nullptr) return std::perror("mkdtemp"), 1;
    const std::filesystem::path dir(dir_template);
    const std::filesystem::path file = dir / "foot.stl";
    if (!kerf::mesh::save_mesh(foot->mesh, file, kerf::LengthUnit::kMillimetre))
        return std::fprintf(stderr, "bench_cut_setup: cannot write %s\n", file.c_str()), 1;
    // The cut: across the first metatarsal's shaft, seeded on its outer surface (mm).
    const kerf::mesh::BoneInfo bone = foot->first_metatarsal();
    const auto axis = (bone.head_m - bone.base_m).normalized();
    const auto at = bone.base_m + axis * (0.5 * (bone.canal_start_m + bone.canal_end_m));
    const auto& m = foot->mesh;
    kerf::mesh::Point seed = at;
    double farthest = -1.0;
    for (std::size_t f = bone.first_triangle; f < bone.first_triangle + bone.triangle_count; ++f) {
        for (const auto h : m.fh_range(kerf::mesh::FaceHandle(static_cast<int>(f)))) {
            const auto p = m.point(m.from_vertex_handle(h)), q = m.point(m.to_vertex_handle(h));
            const double dp = OpenMesh::dot(p - at, axis), dq = OpenMesh::dot(q - at, axis);
            if ((dp < 0) == (dq < 0)) continue;
            const auto x = p + (q - p) * (dp / (dp - dq));
            const double r = (x - at - axis * OpenMesh::dot(x - at, axis)).norm();
            if (r > farthest) farthest = r, seed = x;
        }
    }
    const auto fmt3 = [](const kerf::mesh::Point& p) {
        char b[128];
        std::snprintf(b, sizeof b, "%.9g,%.9g,%.9g", p[0], p[1], p[2]);
        return std::string(b);
    };
    const kerf::mesh::Point at_mm = at * 1e3, seed_mm = seed * 1e3;
    const std::size_t n_faces = m.n_faces();
    foot->mesh = kerf::mesh::make_mesh();  // the children start from the file, not this copy
    // A child's peak resident size (wait4's ru_maxrss) starts at this process's resident size when
    // it forks, whatever it execs: give the freed foot back first, or every child, `kerf cut` and
    // the peer alike, peaks at 170 MiB at least (the 1M foot).
    malloc_trim(0);

    std::vector<double> mesh_b, ctx_b, load_s, build_s, load_cpu, build_cpu, idle_b, idle_cpu,
        build_idle_cpu;
    std::vector<double> kerf_s, kerf_cpu, kerf_peak, peer_s, peer_cpu, peer_peak;
    for (int r = 0; r < reps; ++r) {
        int fds[2];
        if (pipe(fds) != 0) return std::perror("pipe"), 1;
        const pid_t pid = fork();
        if (pid == 0) {
            close(fds[0]);
            const std::string fd = std::to_string(fds[1]);
            execl("/proc/self/exe", argv[0], "--measure", file.c_str(), fd.c_str(), nullptr);
            _exit(127);
        }
        close(fds[1]);
        double out[8];
        const bool got = read(fds[0], out, sizeof out) == static_cast<ssize_t>(sizeof out);
        close(fds[0]);
        int status = 0;
        waitpid(pid, &status, 0);
        if (!got) return std::fprintf(stderr, "bench_cut_setup: child failed\n"), 1;
        mesh_b.push_back(out[0]), ctx_b.push_back(out[1]);
        load_s.push_back(out[2]), build_s.push_back(out[3]);
        load_cpu.push_back(out[4]), build_cpu.push_back(out[5]);
        idle_b.push_back(out[6]), idle_cpu.push_back(out[7]);
        build_idle_cpu.push_back(out[5] + out[7]);
        ProcessCost cost;
        if (!kerf_exe.empty()) {
            if (!run_process(
                    {kerf_exe, "cut", file.string(), "--plane", fmt3(at_mm) + "," + fmt3(axis),
                     "--seed", fmt3(seed_mm), "-o", (dir / "kerf_piece.stl").string()},
                    cost))
                return std::fprintf(stderr, "bench_cut_setup: kerf cut failed\n"), 1;
            kerf_s.push_back(cost.wall_s), kerf_cpu.push_back(cost.cpu_s);
            kerf_peak.push_back(cost.peak_bytes);
        }
        if (!peer_exe.empty()) {
            char plane[256];
            std::snprintf(plane, sizeof plane, "%.9g %.9g %.9g %.9g %.9g %.9g", at_mm[0], at_mm[1],
                          at_mm[2], axis[0], axis[1], axis[2]);
            std::vector<std::string> args{peer_exe, file.string()};
            for (const char* p = plane; *p;) {
                const char* e = p;
                while (*e && *e != ' ') ++e;
                args.emplace_back(p, e);
                p = *e ? e + 1 : e;
            }
            args.push_back((dir / "peer_piece").string());
            if (!run_process(args, cost))
                return std::fprintf(stderr, "bench_cut_setup: %s failed\n", peer_exe.c_str()), 1;
            peer_s.push_back(cost.wall_s), peer_cpu.push_back(cost.cpu_s);
            peer_peak.push_back(cost.peak_bytes);
        }
    }
    std::filesystem::remove_all(dir);

    std::printf("bench_cut_setup: foot, %zu triangles, binary STL; %d repetitions\n", n_faces,
                reps);
    print_spread("mesh resident (after load)", mesh_b, 1.0 / (1 << 20), "MiB");
    print_spread("context resident (added by CutContext)", ctx_b, 1.0 / (1 << 20), "MiB");
    print_spread("context resident after the idle steps", idle_b, 1.0 / (1 << 20), "MiB");
    print_spread("mesh load (load_mesh_owned)", load_s, 1e3, "ms");
    print_spread("context build", build_s, 1e3, "ms");
    print_spread("mesh load cpu", load_cpu, 1e3, "ms");
    print_spread("context build cpu", build_cpu, 1e3, "ms");
    print_spread("idle steps (headroom written) cpu", idle_cpu, 1e3, "ms");
    std::printf("Ratios (same run):\n");
    print_ratio("context memory / mesh memory (<= 0.5)", ctx_b, mesh_b);
    print_ratio("  the same after the idle steps (<= 0.5)", idle_b, mesh_b);
    print_ratio("context build / mesh load (<= 0.3)", build_s, load_s);
    print_ratio("context build / mesh load, cpu (<= 0.3)", build_cpu, load_cpu);
    print_ratio("  the same with the idle steps, cpu", build_idle_cpu, load_cpu);
    if (!kerf_s.empty()) {
        print_spread("kerf cut (process) wall", kerf_s, 1e3, "ms");
        print_spread("kerf cut (process) cpu, user+sys", kerf_cpu, 1e3, "ms");
        print_spread("kerf cut peak resident", kerf_peak, 1.0 / (1 << 20), "MiB");
    }
    if (!peer_s.empty()) {
        print_spread("peer (process) wall", peer_s, 1e3, "ms");
        print_spread("peer (process) cpu, user+sys", peer_cpu, 1e3, "ms");
        print_spread("peer peak resident", peer_peak, 1.0 / (1 << 20), "MiB");
        if (!kerf_s.empty()) {
            print_ratio("kerf cut / peer wall (<= 1)", kerf_s, peer_s);
            print_ratio("kerf cut / peer cpu", kerf_cpu, peer_cpu);
            print_ratio("kerf cut / peer peak resident", kerf_peak, peer_peak);
        }
    }
    return 0;
}
