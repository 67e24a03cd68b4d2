// GLSL ES 3.00 sources of the renderer's programs (internal to kerf_render).
#pragma once

namespace kerf::render::detail {

/// Bone: per-vertex body transform, cortical / canal / cut-surface materials, pores on caps.
extern const char* const kBoneVertexShader;
extern const char* const kBoneFragmentShader;
/// Solid lit objects (blade) and the translucent planned-cut guide: one model matrix, a colour.
extern const char* const kSolidVertexShader;
extern const char* const kSolidFragmentShader;
/// HUD text: stb_easy_font quads in pixels.
extern const char* const kTextVertexShader;
extern const char* const kTextFragmentShader;

}  // namespace kerf::render::detail
