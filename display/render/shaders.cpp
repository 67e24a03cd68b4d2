#include "display/render/shaders.hpp"

namespace kerf::render::detail {

const char* const kBoneVertexShader = R"(#version 300 es
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_plane_uv;
layout(location = 3) in uvec2 a_kind_body;
uniform mat4 u_body[16];
uniform mat4 u_view_proj;
out vec3 v_position;
out vec3 v_normal;
out vec2 v_plane_uv;
out vec2 v_material;  // x: 1 on a cut surface, y: 1 towards the canal
void main() {
    mat4 model = u_body[a_kind_body.y];
    vec4 w = model * vec4(a_position, 1.0);
    v_position = w.xyz;
    v_normal = mat3(model) * a_normal;
    v_plane_uv = a_plane_uv;
    uint kind = a_kind_body.x;
    v_material = vec2(kind >= 2u ? 1.0 : 0.0, (kind == 1u || kind == 3u) ? 1.0 : 0.0);
    gl_Position = u_view_proj * w;
}
)";

// Cut surfaces: a Worley (cellular) pattern in plane coordinates gives the trabecular network of
// cancellous bone: round marrow-filled pores around the cells' feature points, the bone between
// them the trabeculae. Pores widen towards the canal (v_material.y, interpolated from the cap
// corners' rim material) and close up at the cortical rim (compact bone).
const char* const kBoneFragmentShader = R"(#version 300 es
precision highp float;
in vec3 v_position;
in vec3 v_normal;
in vec2 v_plane_uv;
in vec2 v_material;
uniform vec3 u_eye;
uniform float u_pore_scale;  // cells per metre
out vec4 o_color;

vec2 hash2(vec2 p) {
    vec3 q = fract(vec3(p.xyx) * vec3(0.1031, 0.1030, 0.0973));
    q += dot(q, q.yzx + 33.33);
    return fract((q.xx + q.yz) * q.zy);
}
// Distances to the nearest and second-nearest feature points.
vec2 worley(vec2 p) {
    vec2 i = floor(p), f = fract(p);
    float d1 = 8.0, d2 = 8.0;
    for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x) {
            vec2 g = vec2(float(x), float(y));
            vec2 r = g + hash2(i + g) - f;
            float d = dot(r, r);
            if (d < d1) { d2 = d1; d1 = d; } else if (d < d2) { d2 = d; }
        }
    return sqrt(vec2(d1, d2));
}

void main() {
    vec3 n = normalize(v_normal);
    vec3 v = normalize(u_eye - v_position);
    vec3 base;
    float shininess = 24.0, spec_k = 0.25;
    if (v_material.x > 0.5) {
        vec2 c = worley(v_plane_uv * u_pore_scale);
        vec2 c2 = worley(v_plane_uv * u_pore_scale * 2.7 + 17.0);
        // Pore radius (in cells): closed at the cortical rim, wide open towards the canal.
        float radius = mix(0.06, 0.46, pow(v_material.y, 0.7));
        float pore = 1.0 - smoothstep(radius - 0.07, radius + 0.03, c.x);
        float fine = (1.0 - smoothstep(0.05, 0.16, c2.x)) * 0.5 * v_material.y;
        vec3 trabecula = vec3(0.90, 0.83, 0.68);
        vec3 marrow = vec3(0.50, 0.17, 0.12);
        base = mix(trabecula, marrow, clamp(max(pore, fine), 0.0, 1.0));
        base *= 0.92 + 0.08 * c2.x;
        spec_k = 0.06;
        shininess = 8.0;
    } else if (v_material.y > 0.5) {
        base = vec3(0.70, 0.36, 0.26);                 // medullary canal: marrow-lined
        spec_k = 0.12;
    } else {
        base = vec3(0.89, 0.85, 0.74);                 // cortical bone, ivory
    }
    vec3 key = normalize(vec3(0.35, -0.45, 0.82));
    float diffuse = max(dot(n, key), 0.0) * 0.75 + max(dot(n, v), 0.0) * 0.25;
    vec3 h = normalize(key + v);
    float spec = pow(max(dot(n, h), 0.0), shininess) * spec_k;
    vec3 color = base * (0.16 + 0.84 * diffuse) + vec3(spec);
    o_color = vec4(pow(color, vec3(1.0 / 2.2)), 1.0);
}
)";

const char* const kSolidVertexShader = R"(#version 300 es
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_model;
uniform mat4 u_view_proj;
out vec3 v_position;
out vec3 v_normal;
void main() {
    vec4 w = u_model * vec4(a_position, 1.0);
    v_position = w.xyz;
    v_normal = mat3(u_model) * a_normal;
    gl_Position = u_view_proj * w;
}
)";

const char* const kSolidFragmentShader = R"(#version 300 es
precision highp float;
in vec3 v_position;
in vec3 v_normal;
uniform vec3 u_eye;
uniform vec4 u_color;
uniform float u_specular;
out vec4 o_color;
void main() {
    vec3 n = normalize(v_normal);
    vec3 v = normalize(u_eye - v_position);
    if (!gl_FrontFacing) n = -n;
    vec3 key = normalize(vec3(0.35, -0.45, 0.82));
    float diffuse = max(dot(n, key), 0.0) * 0.7 + abs(dot(n, v)) * 0.3;
    vec3 h = normalize(key + v);
    float spec = pow(max(dot(n, h), 0.0), 60.0) * u_specular;
    vec3 color = u_color.rgb * (0.2 + 0.8 * diffuse) + vec3(spec);
    o_color = vec4(pow(color, vec3(1.0 / 2.2)), u_color.a);
}
)";

const char* const kTextVertexShader = R"(#version 300 es
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec4 a_color;
uniform vec2 u_screen;
uniform float u_scale;
uniform vec2 u_offset;
out vec4 v_color;
void main() {
    vec2 p = a_position.xy * u_scale + u_offset;
    v_color = a_color;
    gl_Position = vec4(p.x / u_screen.x * 2.0 - 1.0, 1.0 - p.y / u_screen.y * 2.0, 0.0, 1.0);
}
)";

const char* const kTextFragmentShader = R"(#version 300 es
precision mediump float;
in vec4 v_color;
out vec4 o_color;
void main() { o_color = v_color; }
)";

}  // namespace kerf::render::detail
