#include "display/render/renderer.hpp"

#include <GLES3/gl3.h>
#include <stb_easy_font.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <string>

#include "display/render/shaders.hpp"

namespace kerf::render {

std::string_view to_string(RenderErrc code) noexcept {
    switch (code) {
        case RenderErrc::kBadOption:
            return "bad_option";
        case RenderErrc::kNoContext:
            return "no_context";
        case RenderErrc::kGl:
            return "gl";
        case RenderErrc::kIo:
            return "io";
    }
    return "unknown";
}

namespace {

Err<RenderError> fail(RenderErrc code, std::string what) {
    return Err{RenderError{code, "render", std::move(what)}};
}

// Compiles one shader; on failure writes the info log into `log`.
GLuint compile(GLenum type, const char* src, std::string& log) {
    const GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &src, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char buf[2048] = {};
        glGetShaderInfoLog(s, sizeof buf, nullptr, buf);
        log = buf;
        glDeleteShader(s);
        return 0;
    }
    return s;
}

// Links a program from two sources; 0 and `log` set on failure.
GLuint link(const char* name, const char* vs, const char* fs, std::string& log) {
    const GLuint v = compile(GL_VERTEX_SHADER, vs, log);
    const GLuint f = v ? compile(GL_FRAGMENT_SHADER, fs, log) : 0;
    if (!v || !f) {
        log = std::string(name) + " shader: " + log;
        if (v) glDeleteShader(v);
        return 0;
    }
    const GLuint p = glCreateProgram();
    glAttachShader(p, v);
    glAttachShader(p, f);
    glLinkProgram(p);
    glDeleteShader(v);
    glDeleteShader(f);
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        char buf[2048] = {};
        glGetProgramInfoLog(p, sizeof buf, nullptr, buf);
        log = std::string(name) + " program link: " + buf;
        glDeleteProgram(p);
        return 0;
    }
    return p;
}

struct SolidVertex {
    float position[3];
    float normal[3];
};

// A box [lo, hi] as 12 outward triangles (flat normals), appended to `out`.
void append_box(std::vector<SolidVertex>& out, glm::vec3 lo, glm::vec3 hi) {
    const glm::vec3 c[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z},
                            {lo.x, hi.y, lo.z}, {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z},
                            {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
    const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                             {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
    for (const auto& q : quads) {
        const glm::vec3 n = glm::normalize(glm::cross(c[q[1]] - c[q[0]], c[q[2]] - c[q[0]]));
        for (int k : {0, 1, 2, 0, 2, 3})
            out.push_back({{c[q[k]].x, c[q[k]].y, c[q[k]].z}, {n.x, n.y, n.z}});
    }
}

// The blade in a unit tool frame: edge along x in [-0.5, 0.5], body y in [0, 1], z in
// [-0.5, 0.5] (scaled by length, depth, thickness at draw time), with teeth below the edge.
std::vector<SolidVertex> blade_geometry() {
    std::vector<SolidVertex> v;
    append_box(v, {-0.5f, 0.0f, -0.5f}, {0.5f, 1.0f, 0.5f});
    constexpr int kTeeth = 14;
    for (int i = 0; i < kTeeth; ++i) {  // teeth: triangles in the blade plane, both faces
        const float x0 = -0.5f + static_cast<float>(i) / kTeeth;
        const float x1 = x0 + 1.0f / kTeeth;
        for (float z : {0.5f, -0.5f}) {
            const float nz = z > 0 ? 1.0f : -1.0f;
            const SolidVertex a{{x0, 0.0f, z}, {0, 0, nz}}, b{{x1, 0.0f, z}, {0, 0, nz}},
                t{{x0 + 0.3f / kTeeth, -0.08f, z}, {0, 0, nz}};
            if (z > 0) {
                v.insert(v.end(), {a, t, b});
            } else {
                v.insert(v.end(), {a, b, t});
            }
        }
    }
    return v;
}

// A unit square in the z = 0 plane, [-1, 1]^2, normal +z (the planned-cut guide).
std::vector<SolidVertex> guide_geometry() {
    std::vector<SolidVertex> v;
    const float s[6][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, -1}, {1, 1}, {-1, 1}};
    for (const auto& p : s) v.push_back({{p[0], p[1], 0.0f}, {0, 0, 1}});
    return v;
}

void solid_attributes() {
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(SolidVertex), nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(SolidVertex),
                          reinterpret_cast<const void*>(offsetof(SolidVertex, normal)));
}

constexpr int kMaxTextQuads = 4096;

}  // namespace

struct Renderer::State {
    RendererOptions options;
    GLuint fbo = 0, color_rb = 0, depth_rb = 0;
    GLuint bone_program = 0, solid_program = 0, text_program = 0;
    GLint u_body = -1, u_view_proj = -1, u_eye = -1, u_pore_scale = -1;
    GLint s_model = -1, s_view_proj = -1, s_eye = -1, s_color = -1, s_specular = -1;
    GLint t_screen = -1, t_scale = -1, t_offset = -1;
    GLuint mesh_vao = 0, mesh_vbo = 0, mesh_ibo = 0;
    std::uint64_t vbo_capacity_bytes = 0, ibo_capacity_bytes = 0;
    std::uint32_t triangles = 0;
    ChunkIssue issue;  ///< the bone's draw order and what the frame in flight has issued
    GLuint blade_vao = 0, blade_vbo = 0, guide_vao = 0, guide_vbo = 0;
    GLsizei blade_vertices = 0, guide_vertices = 0;
    GLuint text_vao = 0, text_vbo = 0, text_ibo = 0;
    std::vector<char> text_scratch = std::vector<char>(std::size_t{kMaxTextQuads} * 64);
    std::array<glm::mat4, kMaxBodies> bodies;
    std::optional<PlannedCut> planned;
    glm::mat4 view_proj{1.0f};
    glm::vec3 eye{0.0f};
    UploadStats totals;

    ~State() {
        if (!fbo) return;  // moved-from or never built: nothing to free (context may be gone)
        glDeleteFramebuffers(1, &fbo);
        glDeleteRenderbuffers(1, &color_rb);
        glDeleteRenderbuffers(1, &depth_rb);
        for (GLuint p : {bone_program, solid_program, text_program}) glDeleteProgram(p);
        const GLuint vaos[] = {mesh_vao, blade_vao, guide_vao, text_vao};
        glDeleteVertexArrays(4, vaos);
        const GLuint bufs[] = {mesh_vbo, mesh_ibo, blade_vbo, guide_vbo, text_vbo, text_ibo};
        glDeleteBuffers(6, bufs);
    }

    /// Binds the solid program with `model`, the frame's camera, `color` (alpha) and specular.
    void use_solid(const glm::mat4& model, const glm::vec4& color, float specular) const {
        glUseProgram(solid_program);
        glUniformMatrix4fv(s_model, 1, GL_FALSE, glm::value_ptr(model));
        glUniformMatrix4fv(s_view_proj, 1, GL_FALSE, glm::value_ptr(view_proj));
        glUniform3fv(s_eye, 1, glm::value_ptr(eye));
        glUniform4fv(s_color, 1, glm::value_ptr(color));
        glUniform1f(s_specular, specular);
    }

    Status<RenderError> make_targets();
    Status<RenderError> make_programs();
    void make_geometry();
    void make_mesh_buffers();
};

Status<RenderError> Renderer::State::make_targets() {
    glGenFramebuffers(1, &fbo);
    glGenRenderbuffers(1, &color_rb);
    glGenRenderbuffers(1, &depth_rb);
    glBindRenderbuffer(GL_RENDERBUFFER, color_rb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, options.width, options.height);
    glBindRenderbuffer(GL_RENDERBUFFER, depth_rb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, options.width, options.height);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_rb);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_rb);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "framebuffer %dx%d incomplete (status 0x%04x)",
                      options.width, options.height, status);
        return fail(RenderErrc::kGl, buf);
    }
    return {};
}

Status<RenderError> Renderer::State::make_programs() {
    std::string log;
    bone_program = link("bone", detail::kBoneVertexShader, detail::kBoneFragmentShader, log);
    if (bone_program) {
        solid_program =
            link("solid", detail::kSolidVertexShader, detail::kSolidFragmentShader, log);
    }
    if (solid_program) {
        text_program = link("text", detail::kTextVertexShader, detail::kTextFragmentShader, log);
    }
    if (!text_program) return fail(RenderErrc::kGl, log);
    u_body = glGetUniformLocation(bone_program, "u_body");
    u_view_proj = glGetUniformLocation(bone_program, "u_view_proj");
    u_eye = glGetUniformLocation(bone_program, "u_eye");
    u_pore_scale = glGetUniformLocation(bone_program, "u_pore_scale");
    s_model = glGetUniformLocation(solid_program, "u_model");
    s_view_proj = glGetUniformLocation(solid_program, "u_view_proj");
    s_eye = glGetUniformLocation(solid_program, "u_eye");
    s_color = glGetUniformLocation(solid_program, "u_color");
    s_specular = glGetUniformLocation(solid_program, "u_specular");
    t_screen = glGetUniformLocation(text_program, "u_screen");
    t_scale = glGetUniformLocation(text_program, "u_scale");
    t_offset = glGetUniformLocation(text_program, "u_offset");
    return {};
}

void Renderer::State::make_geometry() {
    const auto make = [](GLuint& vao, GLuint& vbo, const std::vector<SolidVertex>& v) {
        glGenVertexArrays(1, &vao);
        glGenBuffers(1, &vbo);
        glBindVertexArray(vao);
        glBindBuffer(GL_ARRAY_BUFFER, vbo);
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(v.size() * sizeof(SolidVertex)),
                     v.data(), GL_STATIC_DRAW);
        solid_attributes();
        return static_cast<GLsizei>(v.size());
    };
    blade_vertices = make(blade_vao, blade_vbo, blade_geometry());
    guide_vertices = make(guide_vao, guide_vbo, guide_geometry());
    // HUD text: stb_easy_font emits quads of 4 vertices (x, y, z float + RGBA8 = 16 bytes).
    glGenVertexArrays(1, &text_vao);
    glGenBuffers(1, &text_vbo);
    glGenBuffers(1, &text_ibo);
    glBindVertexArray(text_vao);
    glBindBuffer(GL_ARRAY_BUFFER, text_vbo);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 16, nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_UNSIGNED_BYTE, GL_TRUE, 16, reinterpret_cast<void*>(12));
    std::vector<std::uint16_t> quad_indices;
    quad_indices.reserve(std::size_t{kMaxTextQuads} * 6);
    for (int q = 0; q < kMaxTextQuads; ++q) {
        const auto b = static_cast<std::uint16_t>(q * 4);
        for (int k : {0, 1, 2, 0, 2, 3}) quad_indices.push_back(static_cast<std::uint16_t>(b + k));
    }
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, text_ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(quad_indices.size() * sizeof(std::uint16_t)),
                 quad_indices.data(), GL_STATIC_DRAW);
    glBindVertexArray(0);
}

void Renderer::State::make_mesh_buffers() {
    glGenVertexArrays(1, &mesh_vao);
    glGenBuffers(1, &mesh_vbo);
    glGenBuffers(1, &mesh_ibo);
    glBindVertexArray(mesh_vao);
    glBindBuffer(GL_ARRAY_BUFFER, mesh_vbo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, mesh_ibo);
    const auto at = [](std::size_t off) { return reinterpret_cast<const void*>(off); };
    constexpr GLsizei stride = sizeof(RenderVertex);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, at(offsetof(RenderVertex, position)));
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, at(offsetof(RenderVertex, normal)));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, stride, at(offsetof(RenderVertex, plane_uv)));
    glEnableVertexAttribArray(3);
    glVertexAttribIPointer(3, 2, GL_UNSIGNED_BYTE, stride, at(offsetof(RenderVertex, kind)));
    glBindVertexArray(0);
}

Result<Renderer, RenderError> Renderer::create(const RendererOptions& options) {
    if (options.width < 1 || options.height < 1 || options.width > 8192 || options.height > 8192) {
        return fail(RenderErrc::kBadOption, "framebuffer size " + std::to_string(options.width) +
                                                "x" + std::to_string(options.height) +
                                                " is outside 1..8192");
    }
    const char* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    if (!version || std::strncmp(version, "OpenGL ES 3", 11) != 0) {
        return fail(RenderErrc::kNoContext,
                    std::string("needs a current OpenGL ES 3 context, found '") +
                        (version ? version : "no context") + "'");
    }
    auto s = std::make_unique<State>();
    s->options = options;
    s->bodies.fill(glm::mat4(1.0f));
    if (auto st = s->make_targets(); !st) return Err{st.error()};
    if (auto st = s->make_programs(); !st) return Err{st.error()};
    s->make_geometry();
    s->make_mesh_buffers();
    if (const GLenum e = glGetError(); e != GL_NO_ERROR) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "GL error 0x%04x while creating", e);
        return fail(RenderErrc::kGl, buf);
    }
    return Renderer(std::move(s));
}

Renderer::Renderer(std::unique_ptr<State> s) noexcept : s_(std::move(s)) {}
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;
Renderer::~Renderer() = default;

int Renderer::width() const noexcept { return s_->options.width; }
int Renderer::height() const noexcept { return s_->options.height; }
const UploadStats& Renderer::upload_totals() const noexcept { return s_->totals; }

UploadStats Renderer::upload(RenderMesh& mesh) {
    UploadStats u;
    State& s = *s_;
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, s.mesh_vbo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, s.mesh_ibo);
    const auto vbytes = static_cast<std::uint64_t>(mesh.vertices().size_bytes());
    const auto ibytes = static_cast<std::uint64_t>(mesh.indices().size_bytes());
    if (mesh.needs_realloc() || vbytes != s.vbo_capacity_bytes || ibytes != s.ibo_capacity_bytes) {
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vbytes), mesh.vertices().data(),
                     GL_DYNAMIC_DRAW);
        glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(ibytes),
                     mesh.indices().data(), GL_DYNAMIC_DRAW);
        s.vbo_capacity_bytes = vbytes;
        s.ibo_capacity_bytes = ibytes;
        u.bytes = vbytes + ibytes;
        u.reallocated = true;
        mesh.clear_realloc();
    } else {
        s.issue.note_edits(mesh);
        for (const auto& r : mesh.dirty_vertices().ranges()) {
            glBufferSubData(GL_ARRAY_BUFFER,
                            static_cast<GLintptr>(std::uint64_t{r.first} * sizeof(RenderVertex)),
                            static_cast<GLsizeiptr>(std::uint64_t{r.count} * sizeof(RenderVertex)),
                            mesh.vertices().data() + r.first);
            u.bytes += std::uint64_t{r.count} * sizeof(RenderVertex);
            ++u.calls;
        }
        for (const auto& r : mesh.dirty_indices().ranges()) {
            glBufferSubData(GL_ELEMENT_ARRAY_BUFFER,
                            static_cast<GLintptr>(std::uint64_t{r.first} * sizeof(std::uint32_t)),
                            static_cast<GLsizeiptr>(std::uint64_t{r.count} * sizeof(std::uint32_t)),
                            mesh.indices().data() + r.first);
            u.bytes += std::uint64_t{r.count} * sizeof(std::uint32_t);
            ++u.calls;
        }
    }
    mesh.dirty_vertices().clear();
    mesh.dirty_indices().clear();
    s.triangles = mesh.triangle_count();
    s.issue.uploaded(mesh);
    s.totals.bytes += u.bytes;
    s.totals.calls += u.calls;
    s.totals.reallocated = s.totals.reallocated || u.reallocated;
    return u;
}

bool Renderer::join_frame(RenderMesh& mesh, UploadStats& stats) {
    if (!s_->issue.can_join(mesh)) return false;
    stats = upload(mesh);
    return true;
}

void Renderer::set_body_transform(int body, const glm::dmat4& body_to_world) noexcept {
    if (body < 0 || body >= kMaxBodies) return;
    s_->bodies[static_cast<std::size_t>(body)] = glm::mat4(body_to_world);
}

void Renderer::set_body_transform(int body, const std::array<float, 16>& m) noexcept {
    if (body < 0 || body >= kMaxBodies) return;
    s_->bodies[static_cast<std::size_t>(body)] = glm::make_mat4(m.data());
}

void Renderer::set_planned_cut(const std::optional<PlannedCut>& cut) noexcept { s_->planned = cut; }

void Renderer::begin_frame(const Camera& camera) { (void)begin_frame(camera, {}); }

bool Renderer::begin_frame(const Camera& camera, const std::function<bool()>& abandon) {
    State& s = *s_;
    glBindFramebuffer(GL_FRAMEBUFFER, s.fbo);
    glViewport(0, 0, s.options.width, s.options.height);
    glClearColor(s.options.background[0], s.options.background[1], s.options.background[2], 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    const double aspect = static_cast<double>(s.options.width) / s.options.height;
    s.view_proj = camera.projection(aspect) * camera.view();
    s.eye = glm::vec3(camera.eye());
    if (s.triangles > 0) {
        glUseProgram(s.bone_program);
        glUniformMatrix4fv(s.u_body, kMaxBodies, GL_FALSE, glm::value_ptr(s.bodies[0]));
        glUniformMatrix4fv(s.u_view_proj, 1, GL_FALSE, glm::value_ptr(s.view_proj));
        glUniform3fv(s.u_eye, 1, glm::value_ptr(s.eye));
        glUniform1f(s.u_pore_scale, 800.0f);  // ~1.25 mm trabecular cells
        s.issue.begin();
        std::uint32_t first = 0, count = 0;
        for (bool started = false;; started = true) {
            if (started && abandon && abandon()) {
                glBindVertexArray(0);
                return false;
            }
            if (!s.issue.next(first, count)) break;
            glBindVertexArray(s.mesh_vao);  // again: a join_frame() upload unbinds it
            glDrawElements(
                GL_TRIANGLES, static_cast<GLsizei>(count * 3), GL_UNSIGNED_INT,
                reinterpret_cast<const void*>(std::uintptr_t{first} * 3 * sizeof(std::uint32_t)));
        }
    }
    if (s.planned) {
        const PlannedCut& p = *s.planned;
        const glm::dvec3 n = glm::normalize(p.normal);
        const glm::dvec3 a = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
        const glm::dvec3 u = glm::normalize(glm::cross(a, n)), v = glm::cross(n, u);
        glm::dmat4 m(1.0);
        m[0] = glm::dvec4(u * p.half_extent_m, 0);
        m[1] = glm::dvec4(v * p.half_extent_m, 0);
        m[2] = glm::dvec4(n, 0);
        m[3] = glm::dvec4(p.point_m, 1);
        s.use_solid(glm::mat4(m), {0.25f, 0.75f, 0.95f, 0.28f}, 0.0f);
        glEnable(GL_BLEND);
        glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
        glDepthMask(GL_FALSE);
        glDisable(GL_CULL_FACE);
        glBindVertexArray(s.guide_vao);
        glDrawArrays(GL_TRIANGLES, 0, s.guide_vertices);
        glDepthMask(GL_TRUE);
        glDisable(GL_BLEND);
        glEnable(GL_CULL_FACE);
    }
    glBindVertexArray(0);
    return true;
}

BladePose blade_pose_from(const ipc::LatestState& state, const BladePose& like) noexcept {
    BladePose b = like;
    const double* p = state.tool_position_m;
    const double* q = state.tool_orientation_wxyz;
    b.position_m = glm::dvec3(p[0], p[1], p[2]);
    b.orientation = glm::dquat(q[0], q[1], q[2], q[3]);
    const double n = glm::length(b.orientation);
    const bool finite =
        std::isfinite(n) && std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
    if (!finite || n < 1e-9) {
        b.visible = false;
        b.orientation = glm::dquat(1, 0, 0, 0);
        return b;
    }
    b.orientation /= n;
    return b;
}

void Renderer::draw_blade(const BladePose& pose) {
    if (!pose.visible) return;
    State& s = *s_;
    glm::dmat4 m = glm::translate(glm::dmat4(1.0), pose.position_m) *
                   glm::mat4_cast(glm::normalize(pose.orientation)) *
                   glm::scale(glm::dmat4(1.0), glm::dvec3(pose.length_m, pose.depth_m,
                                                          std::max(pose.thickness_m, 1e-5)));
    glBindFramebuffer(GL_FRAMEBUFFER, s.fbo);
    s.use_solid(glm::mat4(m), {0.62f, 0.66f, 0.72f, 1.0f}, 0.8f);
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glBindVertexArray(s.blade_vao);
    glDrawArrays(GL_TRIANGLES, 0, s.blade_vertices);
    glBindVertexArray(0);
    glEnable(GL_CULL_FACE);
}

void Renderer::draw_hud(const HudState& hud) {
    State& s = *s_;
    const std::string text = format_hud(hud);
    glBindFramebuffer(GL_FRAMEBUFFER, s.fbo);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glUseProgram(s.text_program);
    glUniform2f(s.t_screen, static_cast<float>(s.options.width),
                static_cast<float>(s.options.height));
    const float scale = s.options.height >= 600 ? 2.0f : 1.0f;
    glUniform1f(s.t_scale, scale);
    glBindVertexArray(s.text_vao);
    glBindBuffer(GL_ARRAY_BUFFER, s.text_vbo);
    // A dark backing panel (one stb_easy_font-style quad), then a shadow pass, then the text.
    const float w = static_cast<float>(stb_easy_font_width(const_cast<char*>(text.c_str())));
    const float h = static_cast<float>(stb_easy_font_height(const_cast<char*>(text.c_str())));
    struct QuadVertex {
        float x, y, z;
        unsigned char rgba[4];
    };
    const QuadVertex panel[4] = {{-4, -4, 0, {0, 0, 0, 150}},
                                 {w + 4, -4, 0, {0, 0, 0, 150}},
                                 {w + 4, h + 2, 0, {0, 0, 0, 150}},
                                 {-4, h + 2, 0, {0, 0, 0, 150}}};
    glBufferData(GL_ARRAY_BUFFER, sizeof panel, panel, GL_STREAM_DRAW);
    glUniform2f(s.t_offset, 10.0f, 10.0f);
    glDrawElements(GL_TRIANGLES, 6, GL_UNSIGNED_SHORT, nullptr);
    unsigned char shadow[4] = {0, 0, 0, 255}, ink[4] = {235, 240, 200, 255};
    for (int pass = 0; pass < 2; ++pass) {
        int quads =
            stb_easy_font_print(0, 0, const_cast<char*>(text.c_str()), pass ? ink : shadow,
                                s.text_scratch.data(), static_cast<int>(s.text_scratch.size()));
        quads = std::min(quads, kMaxTextQuads);
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(quads) * 64, s.text_scratch.data(),
                     GL_STREAM_DRAW);
        const float off = pass ? 0.0f : 0.5f * scale;
        glUniform2f(s.t_offset, 10.0f + off, 10.0f + off);
        glDrawElements(GL_TRIANGLES, quads * 6, GL_UNSIGNED_SHORT, nullptr);
    }
    glBindVertexArray(0);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
}

void Renderer::finish_frame() { glFinish(); }

void Renderer::present_to(std::uint32_t target, int width, int height) {
    State& s = *s_;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, s.fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
    glBlitFramebuffer(0, 0, s.options.width, s.options.height, 0, 0, width, height,
                      GL_COLOR_BUFFER_BIT, GL_LINEAR);
    glBindFramebuffer(GL_FRAMEBUFFER, s.fbo);
}

std::vector<std::uint8_t> Renderer::read_pixels() {
    State& s = *s_;
    const auto w = static_cast<std::size_t>(s.options.width);
    const auto h = static_cast<std::size_t>(s.options.height);
    std::vector<std::uint8_t> bottom_up(w * h * 4), out(w * h * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, s.fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, s.options.width, s.options.height, GL_RGBA, GL_UNSIGNED_BYTE,
                 bottom_up.data());
    for (std::size_t y = 0; y < h; ++y)
        std::memcpy(out.data() + y * w * 4, bottom_up.data() + (h - 1 - y) * w * 4, w * 4);
    return out;
}

Status<RenderError> Renderer::save_png(const std::string& path) {
    return write_png(path, width(), height(), read_pixels());
}

}  // namespace kerf::render
