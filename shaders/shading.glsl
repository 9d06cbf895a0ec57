// Sampling and shading of the ray caster, exactly as docs/RENDERING.md fixes them: trilinear fetches from the
// brick pool at a leaf's level, central-difference gradients, the transfer function lookup with opacity
// correction, and the Phong headlight. The CPU mirror (reference/cpu_raycaster.cpp) computes the same in double.
// Included by shaders/raycast_common.glsl; no #version line. Needs the define BRICK_BORDER (kBrickBorder).

uniform sampler3D uPool;        // render/brick_pool: R8/R16 UNORM, LINEAR, CLAMP_TO_EDGE
#ifdef DVR_STORED_GRADIENTS
uniform sampler3D uGradientPool;  // render/gradient_pool: RGBA16_SNORM (differences, value), uPool's dims
#endif
uniform uvec3 uPoolSlotGrid;    // slots per axis
uniform float uPoolSlotEdge;    // texels per slot per axis (B + 2 * BRICK_BORDER)
uniform vec3 uPoolTexelSize;    // 1 / pool texture dims
uniform sampler1D uTransferFunction;  // RGBA32F, straight color, LINEAR, CLAMP_TO_EDGE
uniform float uTfEntries;       // N

uniform vec3 uIsoBaseColor;
uniform float uAmbient;
uniform float uDiffuse;
uniform float uSpecular;
uniform float uShininess;

// The pool's uniforms, as the walks read them per leaf: loaded once per ray (WalkUniforms in
// shaders/raycast_common.glsl says why).
struct PoolLayout {
  vec2 slotsPerRowLayer;  // uPoolSlotGrid.x, uPoolSlotGrid.x * uPoolSlotGrid.y
  float slotEdge;         // uPoolSlotEdge
  vec3 texelSize;         // uPoolTexelSize
};

PoolLayout poolLayout() {
  return PoolLayout(vec2(float(uPoolSlotGrid.x), float(uPoolSlotGrid.x * uPoolSlotGrid.y)), uPoolSlotEdge,
                    uPoolTexelSize);
}

// Texel origin of a pool slot; the twin of BrickPoolGeometry::slotOrigin. In float: llvmpipe divides integer
// vectors lane by lane (24 scalar divisions per leaf and SIMD group). Exact while slot < 2^21: the quotients lie
// at least 0.5 / (slots per layer) from an integer, far more than their rounding error.
vec3 poolSlotOrigin(uint slot, PoolLayout pool) {
  float perRow = pool.slotsPerRowLayer.x;
  float perLayer = pool.slotsPerRowLayer.y;
  float s = float(slot);
  float z = floor((s + 0.5) / perLayer);
  float inLayer = s - z * perLayer;
  float y = floor((inLayer + 0.5) / perRow);
  return vec3(inLayer - y * perRow, y, z) * pool.slotEdge;
}

// A data leaf's brick: where its slot lies and how root-cube coordinates map to its texels.
struct BrickRef {
  vec3 slotOrigin;      // texel origin of the slot in the pool
  vec3 boxMin;          // leaf box in root-cube coordinates
  float texelsPerCube;  // level-L samples per root-cube unit: B * 2^depth
};

// Texel coordinate (inside the slot, border included) of a root-cube point: the level-L sample coordinate
// minus the node's first sample plus the border (docs/RENDERING.md "Level grid").
vec3 brickTexel(BrickRef b, vec3 posCube) {
  return (posCube - b.boxMin) * b.texelsPerCube + float(BRICK_BORDER);
}

// v at a texel coordinate of the brick, normalized to [0, 1], interpolated in float from eight texelFetch()es
// and clamped to the slot's outer texel centers (clamp-to-edge of this brick alone). Hardware LINEAR filtering of
// 8-bit textures uses 8-bit weights (llvmpipe, most GPUs): fine for marching, but central-difference gradients
// and the bisected hit of an isosurface then come out blocky and speckled. The iso hit uses this form.
float brickValueExact(BrickRef b, vec3 texel, PoolLayout pool) {
  vec3 q = clamp(texel, vec3(0.5), vec3(pool.slotEdge - 0.5)) - 0.5;
  vec3 base = min(floor(q), vec3(pool.slotEdge - 2.0));  // the upper corner stays inside the slot
  vec3 f = q - base;
  ivec3 i = ivec3(b.slotOrigin + base);
  float c000 = texelFetch(uPool, i, 0).r;
  float c100 = texelFetch(uPool, i + ivec3(1, 0, 0), 0).r;
  float c010 = texelFetch(uPool, i + ivec3(0, 1, 0), 0).r;
  float c110 = texelFetch(uPool, i + ivec3(1, 1, 0), 0).r;
  float c001 = texelFetch(uPool, i + ivec3(0, 0, 1), 0).r;
  float c101 = texelFetch(uPool, i + ivec3(1, 0, 1), 0).r;
  float c011 = texelFetch(uPool, i + ivec3(0, 1, 1), 0).r;
  float c111 = texelFetch(uPool, i + ivec3(1, 1, 1), 0).r;
  float c00 = mix(c000, c100, f.x), c10 = mix(c010, c110, f.x);
  float c01 = mix(c001, c101, f.x), c11 = mix(c011, c111, f.x);
  return mix(mix(c00, c10, f.y), mix(c01, c11, f.y), f.z);
}

// brickGradient() from brickValueExact(): the isosurface normal.
vec3 brickGradientExact(BrickRef b, vec3 texel, vec3 cellWorld, PoolLayout pool) {
  const vec3 dx = vec3(1.0, 0.0, 0.0), dy = vec3(0.0, 1.0, 0.0), dz = vec3(0.0, 0.0, 1.0);
  vec3 g;
  g.x = brickValueExact(b, texel + dx, pool) - brickValueExact(b, texel - dx, pool);
  g.y = brickValueExact(b, texel + dy, pool) - brickValueExact(b, texel - dy, pool);
  g.z = brickValueExact(b, texel + dz, pool) - brickValueExact(b, texel - dz, pool);
  return g / (2.0 * cellWorld);
}

// The sample loops' value and (computed DVR) differences, at a pool coordinate the walks compute once per
// sample (LeafPoolRay in shaders/raycast_common.glsl): the six neighbours are one pool texel away. Samples of a
// leaf lie at texels [BRICK_BORDER, B + BRICK_BORDER] of its slot, so for BRICK_BORDER >= 2 every neighbour
// stays inside the slot without a clamp.
float poolValue(vec3 poolCoord) {
  return textureLod(uPool, poolCoord, 0.0).r;
}

// Central differences v(x+h) - v(x-h) per axis of a LINEAR 3D texture's red channel at texture coordinate p, h
// one texel (texel: its size in texture coordinates). The gradient is these times 1 / (2 h_i), h_i = s_i * 2^L
// (cellWorld), as docs/RENDERING.md fixes it; walkDvr keeps that factor per leaf, since a division per sample
// costs llvmpipe more than the rest of the arithmetic of a sample.
vec3 centralDifferences(sampler3D volume, vec3 p, vec3 texel) {
  vec3 dx = vec3(texel.x, 0.0, 0.0);
  vec3 dy = vec3(0.0, texel.y, 0.0);
  vec3 dz = vec3(0.0, 0.0, texel.z);
  return vec3(textureLod(volume, p + dx, 0.0).r - textureLod(volume, p - dx, 0.0).r,
              textureLod(volume, p + dy, 0.0).r - textureLod(volume, p - dy, 0.0).r,
              textureLod(volume, p + dz, 0.0).r - textureLod(volume, p - dz, 0.0).r);
}

// A DVR sample: its value, and with stored gradients the central differences v(x+h) - v(x-h) per axis
// (render/gradient_pool.h) from the same lookup.
struct PoolSample {
  float value;
  vec3 differences;
};

PoolSample poolSample(vec3 poolCoord) {
  PoolSample s;
#ifdef DVR_STORED_GRADIENTS
  vec4 texel = textureLod(uGradientPool, poolCoord, 0.0);
  s.value = texel.a;
  s.differences = texel.rgb;
#else
  s.value = poolValue(poolCoord);
  s.differences = vec3(0.0);
#endif
  return s;
}

// The central differences of a sample, asked for only where it is shaded: without stored gradients, six more
// lookups one texel (pool.texelSize, read once per ray) apart.
vec3 poolSampleDifferences(PoolSample s, vec3 poolCoord, PoolLayout pool) {
#ifdef DVR_STORED_GRADIENTS
  return s.differences;
#else
  return centralDifferences(uPool, poolCoord, pool.texelSize);
#endif
}

// The uniforms that every DVR sample reads for its color, loaded once per ray (WalkUniforms in
// shaders/raycast_common.glsl says why).
struct DvrUniforms {
  float tfEntries;  // uTfEntries
  vec4 phong;       // uAmbient, uDiffuse, uSpecular, uShininess
};

DvrUniforms dvrUniforms() { return DvrUniforms(uTfEntries, vec4(uAmbient, uDiffuse, uSpecular, uShininess)); }

// Transfer function at normalized value v: linear between entries, texcoord (v (N-1) + 0.5) / N.
vec4 transferFunction(float v, DvrUniforms du) {
  float u = (clamp(v, 0.0, 1.0) * (du.tfEntries - 1.0) + 0.5) / du.tfEntries;
  return textureLod(uTransferFunction, u, 0.0);
}

// Phong headlight (L = V = -dir, R = reflect(-L, N)): x = N.L, y = R.V.
vec2 headlight(vec3 n, vec3 dir) {
  vec3 l = -dir;
  vec3 r = reflect(-l, n);
  return vec2(dot(n, l), dot(r, l));
}

vec3 shadeIso(vec3 gradient, vec3 dir) {
  float len = length(gradient);
  vec3 n = len > 0.0 ? -gradient / len : -dir;
  if (dot(n, -dir) < 0.0) n = -n;
  vec2 nlrv = headlight(n, dir);
  return uIsoBaseColor * (uAmbient + uDiffuse * max(nlrv.x, 0.0)) +
         vec3(uSpecular * pow(max(nlrv.y, 0.0), uShininess));
}

// Two-sided shading of a DVR sample's color; unshaded where the gradient vanishes.
vec3 shadeDvr(vec3 color, vec3 gradient, vec3 dir, float minSpacing, DvrUniforms du) {
  float len = length(gradient);
  if (!(len * minSpacing > DVR_SHADE_GRADIENT_THRESHOLD)) return color;
  vec2 nlrv = headlight(-gradient / len, dir);
  vec4 phong = du.phong;
  return color * (phong.x + phong.y * abs(nlrv.x)) + vec3(phong.z * pow(abs(nlrv.y), phong.w));
}
