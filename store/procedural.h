// Procedural scalar fields (`procedural:NAME:SIZE`): pure functions of a position, so a volume of any size
// can be generated slab by slab or brick by brick, and an octree node can be given a conservative min/max
// without generating it. Owned by loader/ (used by the procedural VolumeSource and procedural bricks). Pure
// functions, any thread.
//
// Positions are in level-0 sample coordinates of a SIZE^3 volume: sample (i, j, k) sits at (i+0.5, j+0.5,
// k+0.5) and the volume spans [0, SIZE]^3. Positions outside are clamped onto it. Values are in [0, 255]; a
// uint8 sample is the value rounded to nearest (quantizeProcedural).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <glm/vec3.hpp>

namespace ropecast {

enum class ProceduralKind : uint8_t {
  Sphere,         // smooth radial ramp: 255 at the center, linear to 0; value 127.5 at radius 0.4*SIZE
  Menger,         // Menger (Sierpinski) sponge: 255 in solid, 0 in holes, floor(log3(SIZE)) levels
  Noise,          // hypertexture: a sphere's density ramp displaced by fractal gradient noise
  MarschnerLobb,  // Marschner-Lobb test signal (fM = 6, alpha = 0.25) on [-1,1]^3, [0,1] mapped to [0,255]
};

struct ProceduralField {
  ProceduralKind kind = ProceduralKind::Sphere;
  uint32_t size = 0;  // samples per axis (the volume is size^3)
};

// An axis-aligned box of positions (sample coordinates, see above), bounds included.
struct PositionBox {
  glm::dvec3 lo{0.0};
  glm::dvec3 hi{0.0};
};

// Bounds on values: min <= value <= max.
struct ValueRange {
  double min = 0.0;
  double max = 0.0;
};

inline constexpr uint32_t kMaxProceduralSize = 65536;

// What names a procedural volume instead of a file: "procedural:NAME:SIZE".
inline constexpr std::string_view kProceduralPrefix = "procedural:";
inline bool isProceduralSpec(std::string_view input) {
  return input.starts_with(kProceduralPrefix);
}
// "NAME:SIZE" of a spec, with or without the prefix.
inline std::string_view proceduralNameAndSize(std::string_view spec) {
  return isProceduralSpec(spec) ? spec.substr(kProceduralPrefix.size()) : spec;
}
// The spec that names `field`: "procedural:NAME:SIZE".
std::string proceduralSpecOf(const ProceduralField& field);

// "sphere", "menger", "noise", "marschner-lobb".
std::string_view proceduralKindName(ProceduralKind kind);
std::optional<ProceduralKind> parseProceduralKind(std::string_view name);
// The valid names, comma separated, for error messages.
std::string proceduralKindNames();

// Parses "NAME:SIZE" (the part of a spec after "procedural:"). Throws ropecast::Error naming the spec and
// listing the valid names if NAME is unknown or SIZE is not an integer in [1, kMaxProceduralSize].
ProceduralField parseProceduralField(std::string_view nameAndSize);

// The field's value at position p, in [0, 255].
double proceduralValue(const ProceduralField& field, glm::dvec3 p);

// The uint8 sample value of the field at sample (i, j, k): proceduralValue at (i+0.5, j+0.5, k+0.5), rounded.
uint8_t proceduralSample(const ProceduralField& field, uint32_t i, uint32_t j, uint32_t k);

// Conservative bounds of proceduralValue over every position in `box` (not necessarily tight), widened to
// whole numbers so they bound the rounded uint8 samples as well. Box-filtered (averaged) values of the
// covered samples, as in inner octree nodes, stay inside the same bounds.
ValueRange proceduralRange(const ProceduralField& field, const PositionBox& box);

}  // namespace ropecast
