// format_report_text() and format_report_json(), declared in validate.hpp.
#include <cmath>
#include <cstdio>
#include <string>

#include "display/mesh/validate.hpp"

namespace kerf::mesh {
namespace {

std::string fmt(int decimals, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    return buf;
}

std::string significant(double v) {  // 7 significant digits, any magnitude
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.7g", v);
    return buf;
}

std::string json_number(double v) {
    if (!std::isfinite(v)) return "null";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

std::string point_text(const Point& p, double scale) {
    return "(" + fmt(4, p[0] / scale) + ", " + fmt(4, p[1] / scale) + ", " + fmt(4, p[2] / scale) +
           ")";
}

std::string point_json(const Point& p) {
    return "[" + json_number(p[0]) + ", " + json_number(p[1]) + ", " + json_number(p[2]) + "]";
}

std::string yes_no(bool b) { return b ? "yes" : "no"; }

std::string shell_line(std::size_t i, const ShellSummary& s, double scale, std::string_view u) {
    std::string line = "  shell " + std::to_string(i) + ": " + std::to_string(s.triangles) +
                       " triangles, " + std::to_string(s.vertices) + " vertices, ";
    line += s.closed ? "closed, genus " + std::to_string((2 - s.euler_characteristic) / 2)
                     : "open (" + std::to_string(s.boundary_edges) + " boundary edges)";
    line += ", volume " + significant(s.volume_m3 / (scale * scale * scale)) + " " +
            std::string(u) + "^3\n";
    return line;
}

}  // namespace

std::string format_report_text(const ValidationReport& r, LengthUnit units) {
    const double s = metres_per_unit(units);
    const std::string u{to_string(units)};
    std::string out;
    out += "vertices:              " + std::to_string(r.vertices);
    if (r.unreferenced_vertices > 0) {
        out += " (" + std::to_string(r.unreferenced_vertices) + " unreferenced)";
    }
    out += "\ntriangles:             " + std::to_string(r.triangles) + "\n";
    out += "edges:                 " + std::to_string(r.edges) + "\n";
    out += "closed:                " + yes_no(r.closed) + " (" + std::to_string(r.boundary_edges) +
           " boundary edges)\n";
    out += "non-manifold edges:    " + std::to_string(r.non_manifold_edges) + "\n";
    out += "non-manifold vertices: " + std::to_string(r.non_manifold_vertices) + "\n";
    out += "oriented:              " + yes_no(r.oriented) + " (" +
           std::to_string(r.misoriented_edges) + " edges traversed twice the same way)\n";
    out += "degenerate triangles:  " + std::to_string(r.degenerate_triangles) + "\n";
    if (r.detached_triangles > 0) {
        out += "detached triangles:    " + std::to_string(r.detached_triangles) +
               " (OpenMesh could not connect them; kept as separate triangles)\n";
    }
    out += "shells:                " + std::to_string(r.shells.size()) + "\n";
    const Point size = r.bbox_max_m - r.bbox_min_m;
    out += "bounding box:          " + point_text(r.bbox_min_m, s) + " to " +
           point_text(r.bbox_max_m, s) + " " + u + "\n";
    out += "size:                  " + fmt(3, size[0] / s) + " x " + fmt(3, size[1] / s) + " x " +
           fmt(3, size[2] / s) + " " + u + "\n";
    out += "surface area:          " + significant(r.area_m2 / (s * s)) + " " + u + "^2\n";
    out += "signed volume:         " + significant(r.volume_m3 / (s * s * s)) + " " + u + "^3" +
           (r.closed ? "" : " (mesh is open: not a true volume)") + "\n";
    for (std::size_t i = 0; i < r.shells.size() && i < 40; ++i) {
        out += shell_line(i, r.shells[i], s, u);
    }
    if (r.shells.size() > 40) out += "  ... " + std::to_string(r.shells.size() - 40) + " more\n";
    for (const auto& e : r.boundary_samples_m) {
        out +=
            "  boundary edge " + point_text(e[0], s) + " - " + point_text(e[1], s) + " " + u + "\n";
    }
    return out;
}

std::string format_report_json(const ValidationReport& r) {
    auto field = [](const char* k, const std::string& v) {
        return "\"" + std::string(k) + "\": " + v;
    };
    auto num = [](std::size_t v) { return std::to_string(v); };
    std::string out = "{";
    out += field("vertices", num(r.vertices)) + ", ";
    out += field("unreferenced_vertices", num(r.unreferenced_vertices)) + ", ";
    out += field("triangles", num(r.triangles)) + ", ";
    out += field("edges", num(r.edges)) + ", ";
    out += field("closed", r.closed ? "true" : "false") + ", ";
    out += field("boundary_edges", num(r.boundary_edges)) + ", ";
    out += field("non_manifold_edges", num(r.non_manifold_edges)) + ", ";
    out += field("non_manifold_vertices", num(r.non_manifold_vertices)) + ", ";
    out += field("oriented", r.oriented ? "true" : "false") + ", ";
    out += field("misoriented_edges", num(r.misoriented_edges)) + ", ";
    out += field("degenerate_triangles", num(r.degenerate_triangles)) + ", ";
    out += field("detached_triangles", num(r.detached_triangles)) + ", ";
    out += field("bbox_min_m", point_json(r.bbox_min_m)) + ", ";
    out += field("bbox_max_m", point_json(r.bbox_max_m)) + ", ";
    out += field("area_m2", json_number(r.area_m2)) + ", ";
    out += field("volume_m3", json_number(r.volume_m3)) + ", ";
    out += "\"shells\": [";
    for (std::size_t i = 0; i < r.shells.size(); ++i) {
        const ShellSummary& s = r.shells[i];
        out += std::string(i ? ", " : "") + "{" + field("triangles", num(s.triangles)) + ", " +
               field("vertices", num(s.vertices)) + ", " + field("edges", num(s.edges)) + ", " +
               field("boundary_edges", num(s.boundary_edges)) + ", " +
               field("closed", s.closed ? "true" : "false") + ", " +
               field("euler_characteristic", std::to_string(s.euler_characteristic)) + ", " +
               field("area_m2", json_number(s.area_m2)) + ", " +
               field("volume_m3", json_number(s.volume_m3)) + "}";
    }
    out += "], \"boundary_samples_m\": [";
    for (std::size_t i = 0; i < r.boundary_samples_m.size(); ++i) {
        out += std::string(i ? ", " : "") + "[" + point_json(r.boundary_samples_m[i][0]) + ", " +
               point_json(r.boundary_samples_m[i][1]) + "]";
    }
    out += "]}";
    return out;
}

}  // namespace kerf::mesh
