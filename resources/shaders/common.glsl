// Shared declarations of the Fray renderer's shaders: one descriptor set for
// the whole frame (see renderer/src/renderer.cpp, struct FrameUniforms).

layout(set = 0, binding = 0) uniform FrameUniforms {
    mat4 viewProj;
    mat4 lightViewProj;
    vec4 cameraPos;      // xyz
    vec4 lightDir;       // xyz: direction the light travels (unit)
    vec4 lightColor;     // rgb (linear)
    vec4 skyColor;       // rgb (linear), ambient from above
    vec4 groundColor;    // rgb (linear), ambient from below
    vec4 floorColor;     // rgb (display)
    vec4 floorArea;      // xy: centre (x, z), z: half extent, w: fog start
    vec4 bitmapRect;     // min.x, min.z, max.x, max.z
    vec4 floorParams;    // x: bitmap opacity (0: none), y: grid on, z: fog end
    vec4 shadowParams;   // x: on, y: texel size in uv, z: normal offset (m), w: depth bias (x, y informative)
    vec4 highlightColor; // rgb (display)
    vec4 fogColor;       // rgb (display): the clear colour
} frame;

struct Instance {
    uint paletteOffset;  // first joint of this character in `joints`
    uint flags;          // bit 0: selected
    uint pad0;
    uint pad1;
    vec4 tint;           // rgb (display)
};

layout(std430, set = 0, binding = 1) readonly buffer Instances { Instance instances[]; };

struct JointTransform {
    vec4 position;  // xyz, world
    vec4 rotation;  // unit quaternion (x, y, z, w), world
};

layout(std430, set = 0, binding = 2) readonly buffer Palette { JointTransform joints[]; };

layout(set = 0, binding = 3) uniform sampler2DShadow shadowMap;
layout(set = 0, binding = 4) uniform sampler2D floorBitmap;
layout(set = 0, binding = 5) uniform sampler2D fontAtlas;

vec3 rotateByQuat(vec4 q, vec3 v) {
    vec3 t = 2.0 * cross(q.xyz, v);
    return v + q.w * t + cross(q.xyz, t);
}

// Display colours are sRGB-like; lighting is done in linear space. Gamma 2
// (square / square root) instead of 2.2: pow() costs more than everything
// else in a fragment on lavapipe, and the difference is not visible here.
vec3 toLinear(vec3 c) { return c * c; }
vec3 toDisplay(vec3 c) { return sqrt(clamp(c, 0.0, 1.0)); }

// Shadows on or off per pipeline (a branch on a uniform still runs the
// texture fetch on lavapipe, where each fetch is expensive).
layout(constant_id = 0) const bool kShadows = true;

// Fraction of the light reaching a point; 1 outside the shadow map. One
// comparison fetch: with linear filtering (where the depth format supports
// it) that is a 2x2 percentage-closer filter.
float sunVisibility(vec3 worldPos, vec3 normal) {
    if (!kShadows) return 1.0;
    vec3 p = worldPos + normal * frame.shadowParams.z;
    vec4 clip = frame.lightViewProj * vec4(p, 1.0);
    vec3 ndc = clip.xyz / clip.w;
    vec2 uv = ndc.xy * 0.5 + 0.5;
    if (uv.x <= 0.0 || uv.y <= 0.0 || uv.x >= 1.0 || uv.y >= 1.0 || ndc.z >= 1.0) return 1.0;
    return texture(shadowMap, vec3(uv, ndc.z - frame.shadowParams.w));
}

vec3 ambientLight(vec3 n) { return mix(frame.groundColor.rgb, frame.skyColor.rgb, n.y * 0.5 + 0.5); }
