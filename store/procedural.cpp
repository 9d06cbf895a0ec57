#include "store/procedural.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "core/error.h"

namespace ropecast {
namespace {

constexpr std::array<std::pair<ProceduralKind, std::string_view>, 4> kNames{{
    {ProceduralKind::Sphere, "sphere"},
    {ProceduralKind::Menger, "menger"},
    {ProceduralKind::Noise, "noise"},
    {ProceduralKind::MarschnerLobb, "marschner-lobb"},
}};

glm::dvec3 clampToVolume(glm::dvec3 p, uint32_t size) {
  return glm::clamp(p, glm::dvec3(0.0), glm::dvec3(size));
}

PositionBox clampToVolume(const PositionBox& box, uint32_t size) {
  return {clampToVolume(glm::min(box.lo, box.hi), size), clampToVolume(glm::max(box.lo, box.hi), size)};
}

// Nearest and farthest distance from point c to the points of box.
std::pair<double, double> distanceRange(glm::dvec3 c, const PositionBox& box) {
  const glm::dvec3 outside = glm::max(glm::max(box.lo - c, c - box.hi), glm::dvec3(0.0));
  const glm::dvec3 farthest = glm::max(glm::abs(box.lo - c), glm::abs(box.hi - c));
  return {glm::length(outside), glm::length(farthest)};
}

// Widens to whole numbers inside [0, 255] so the bounds also hold for rounded samples.
ValueRange wholeRange(double lo, double hi) {
  return {std::clamp(std::floor(lo), 0.0, 255.0), std::clamp(std::ceil(hi), 0.0, 255.0)};
}

// ---- sphere: 255 at the center, falling linearly to 0 at radius 0.8*SIZE (127.5 at 0.4*SIZE).

double sphereOfRadius(double r, uint32_t size) {
  return 255.0 * std::clamp(1.0 - r / (0.8 * size), 0.0, 1.0);
}

double sphereValue(glm::dvec3 p, uint32_t size) {
  return sphereOfRadius(glm::length(p - glm::dvec3(0.5 * size)), size);
}

ValueRange sphereRange(const PositionBox& box, uint32_t size) {
  const auto [rMin, rMax] = distanceRange(glm::dvec3(0.5 * size), box);
  return wholeRange(sphereOfRadius(rMax, size), sphereOfRadius(rMin, size));
}

// ---- menger: the cube [0,1]^3 split in 3x3x3 cells per level; a cell with at least two middle coordinates
// is a hole. Levels: as many as keep the smallest hole >= 1 sample.

uint32_t mengerLevels(uint32_t size) {
  uint32_t levels = 0;
  for (uint64_t cells = 3; cells <= size; cells *= 3) ++levels;
  return levels;
}

bool isHoleCell(int dx, int dy, int dz) {
  return (dx == 1) + (dy == 1) + (dz == 1) >= 2;
}

double mengerValue(glm::dvec3 p, uint32_t size) {
  const uint32_t levels = mengerLevels(size);
  glm::dvec3 u = clampToVolume(p, size) / double(size);
  for (uint32_t level = 0; level < levels; ++level) {
    u *= 3.0;
    const glm::dvec3 digit = glm::min(glm::floor(u), glm::dvec3(2.0));
    if (isHoleCell(int(digit.x), int(digit.y), int(digit.z))) return 0.0;
    u -= digit;
  }
  return 255.0;
}

enum : unsigned { kHasHole = 1, kHasSolid = 2 };

// What the cell at `cellLo` (edge `cellSize`, normalized, `level` subdivisions deep) may contain inside the
// closed box [lo, hi]. Stops as soon as both holes and solid are found.
unsigned mengerClassify(glm::dvec3 lo, glm::dvec3 hi, glm::dvec3 cellLo, double cellSize, uint32_t level,
                        uint32_t levels) {
  if (level == levels) return kHasSolid;
  const double sub = cellSize / 3.0;
  unsigned found = 0;
  for (int dz = 0; dz < 3; ++dz) {
    for (int dy = 0; dy < 3; ++dy) {
      for (int dx = 0; dx < 3; ++dx) {
        const glm::dvec3 subLo = cellLo + glm::dvec3(dx, dy, dz) * sub;
        const glm::dvec3 subHi = subLo + glm::dvec3(sub);
        if (glm::any(glm::lessThan(hi, subLo)) || glm::any(glm::greaterThan(lo, subHi))) continue;
        found |= isHoleCell(dx, dy, dz) ? unsigned(kHasHole)
                                        : mengerClassify(lo, hi, subLo, sub, level + 1, levels);
        if (found == (kHasHole | kHasSolid)) return found;
      }
    }
  }
  return found;
}

ValueRange mengerRange(const PositionBox& box, uint32_t size) {
  // Widen by a relative epsilon so positions on a cell boundary count for both cells.
  constexpr double kEdge = 1e-12;
  const unsigned found = mengerClassify(box.lo / double(size) - kEdge, box.hi / double(size) + kEdge,
                                        glm::dvec3(0.0), 1.0, 0, mengerLevels(size));
  return {(found & kHasHole) ? 0.0 : 255.0, (found & kHasSolid) ? 255.0 : 0.0};
}

// ---- noise: hypertexture (Crassin et al. 2008, Sect. 6.3, after Perlin & Hoffert):
// opacity = f(d(X) + k*P(X)), with d the signed distance to a sphere, P fractal gradient noise and f a linear
// ramp. Lengths in units of SIZE.

constexpr double kNoiseRadius = 0.3;     // sphere the noise displaces
constexpr double kNoiseRamp = 0.02;      // half-width of the 0..255 ramp across the surface
constexpr double kNoiseGain = 0.08;      // amplitude of the first octave
constexpr double kNoiseBaseCells = 4.0;  // lattice cells across the volume in the first octave
constexpr uint32_t kNoiseMaxOctaves = 12;

// Octaves down to a wavelength of 2 samples.
uint32_t noiseOctaves(uint32_t size) {
  uint32_t octaves = 1;
  while (octaves < kNoiseMaxOctaves &&
         double(size) / (kNoiseBaseCells * std::ldexp(1.0, int(octaves))) >= 2.0)
    ++octaves;
  return octaves;
}

double noiseAmplitude(uint32_t octaves) {
  return kNoiseGain * (2.0 - std::ldexp(1.0, 1 - int(octaves)));
}

uint32_t latticeHash(int64_t x, int64_t y, int64_t z, uint32_t octave) {
  uint64_t h = uint64_t(x) * 0x9E3779B97F4A7C15ull ^ uint64_t(y) * 0xC2B2AE3D27D4EB4Full ^
               uint64_t(z) * 0x165667B19E3779F9ull ^ uint64_t(octave) * 0x27D4EB2F165667C5ull;
  h ^= h >> 31;
  h *= 0xBF58476D1CE4E5B9ull;
  h ^= h >> 29;
  return uint32_t(h >> 32);
}

// Dot product with one of Perlin's 12 edge gradients (improved noise, 2002).
double gradientDot(uint32_t hash, double x, double y, double z) {
  static constexpr double kGradients[12][3] = {{1, 1, 0}, {-1, 1, 0}, {1, -1, 0}, {-1, -1, 0},
                                               {1, 0, 1}, {-1, 0, 1}, {1, 0, -1}, {-1, 0, -1},
                                               {0, 1, 1}, {0, -1, 1}, {0, 1, -1}, {0, -1, -1}};
  const double* g = kGradients[hash % 12];
  return g[0] * x + g[1] * y + g[2] * z;
}

double fade(double t) {
  return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

// Gradient noise in [-1, 1] (clamped, so the amplitude bound used by the range is exact).
double gradientNoise(glm::dvec3 q, uint32_t octave) {
  const glm::dvec3 cell = glm::floor(q);
  const glm::dvec3 f = q - cell;
  const int64_t x = int64_t(cell.x), y = int64_t(cell.y), z = int64_t(cell.z);
  double corner[8];
  for (int c = 0; c < 8; ++c) {
    const int cx = c & 1, cy = (c >> 1) & 1, cz = (c >> 2) & 1;
    corner[c] = gradientDot(latticeHash(x + cx, y + cy, z + cz, octave), f.x - cx, f.y - cy, f.z - cz);
  }
  const double u = fade(f.x), v = fade(f.y), w = fade(f.z);
  auto lerp = [](double a, double b, double t) { return a + t * (b - a); };
  const double x00 = lerp(corner[0], corner[1], u), x10 = lerp(corner[2], corner[3], u);
  const double x01 = lerp(corner[4], corner[5], u), x11 = lerp(corner[6], corner[7], u);
  return std::clamp(lerp(lerp(x00, x10, v), lerp(x01, x11, v), w), -1.0, 1.0);
}

double noiseRamp(double displacedDistance) {
  return 255.0 * std::clamp(0.5 + displacedDistance / (2.0 * kNoiseRamp), 0.0, 1.0);
}

double noiseValue(glm::dvec3 p, uint32_t size) {
  const glm::dvec3 u = clampToVolume(p, size) / double(size);
  const double distance = kNoiseRadius - glm::length(u - glm::dvec3(0.5));  // > 0 inside
  const uint32_t octaves = noiseOctaves(size);
  const double amplitude = noiseAmplitude(octaves);
  // Far from the surface no noise can reach the ramp: skip evaluating it.
  if (distance - amplitude >= kNoiseRamp) return 255.0;
  if (distance + amplitude <= -kNoiseRamp) return 0.0;
  double displacement = 0.0;
  for (uint32_t octave = 0; octave < octaves; ++octave) {
    const double scale = std::ldexp(1.0, int(octave));
    displacement += kNoiseGain / scale * gradientNoise(u * (kNoiseBaseCells * scale), octave);
  }
  return noiseRamp(distance + displacement);
}

ValueRange noiseRange(const PositionBox& box, uint32_t size) {
  const PositionBox unit{box.lo / double(size), box.hi / double(size)};
  const auto [rMin, rMax] = distanceRange(glm::dvec3(0.5), unit);
  const double amplitude = noiseAmplitude(noiseOctaves(size));
  return wholeRange(noiseRamp(kNoiseRadius - rMax - amplitude), noiseRamp(kNoiseRadius - rMin + amplitude));
}

// ---- Marschner-Lobb (Marschner & Lobb 1994): rho(x,y,z) = (1 - sin(pi z/2) + alpha (1 + rho_r(r))) / (2 (1
// + alpha)), rho_r(r) = cos(2 pi fM cos(pi r / 2)), r = sqrt(x^2 + y^2), on [-1,1]^3.

constexpr double kLobbFm = 6.0;
constexpr double kLobbAlpha = 0.25;

double lobbOf(double zTerm, double cosTerm) {
  return 255.0 * (zTerm + kLobbAlpha * (1.0 + cosTerm)) / (2.0 * (1.0 + kLobbAlpha));
}

double lobbPhase(double r) {
  return 2.0 * std::numbers::pi * kLobbFm * std::cos(std::numbers::pi * r / 2.0);
}

double marschnerLobbValue(glm::dvec3 p, uint32_t size) {
  const glm::dvec3 x = clampToVolume(p, size) / double(size) * 2.0 - 1.0;
  const double r = std::sqrt(x.x * x.x + x.y * x.y);
  return lobbOf(1.0 - std::sin(std::numbers::pi * x.z / 2.0), std::cos(lobbPhase(r)));
}

// Range of cos over [a, b].
std::pair<double, double> cosRange(double a, double b) {
  const double twoPi = 2.0 * std::numbers::pi;
  double lo = std::min(std::cos(a), std::cos(b));
  double hi = std::max(std::cos(a), std::cos(b));
  if (std::floor(b / twoPi) > std::floor(a / twoPi) || std::fmod(a, twoPi) == 0.0)
    hi = 1.0;  // a multiple of 2pi
  const double shifted = std::numbers::pi;
  if (std::floor((b - shifted) / twoPi) > std::floor((a - shifted) / twoPi)) lo = -1.0;  // pi + 2k pi inside
  return {lo, hi};
}

ValueRange marschnerLobbRange(const PositionBox& box, uint32_t size) {
  const glm::dvec3 lo = box.lo / double(size) * 2.0 - 1.0;
  const glm::dvec3 hi = box.hi / double(size) * 2.0 - 1.0;
  const double zTermMin = 1.0 - std::sin(std::numbers::pi * hi.z / 2.0);  // decreasing in z on [-1, 1]
  const double zTermMax = 1.0 - std::sin(std::numbers::pi * lo.z / 2.0);
  const PositionBox xy{{lo.x, lo.y, 0.0}, {hi.x, hi.y, 0.0}};
  const auto [rMin, rMax] = distanceRange(glm::dvec3(0.0), xy);
  // r <= sqrt(2) < 2, where the phase decreases with r.
  const auto [cosMin, cosMax] = cosRange(lobbPhase(rMax), lobbPhase(rMin));
  return wholeRange(lobbOf(zTermMin, cosMin), lobbOf(zTermMax, cosMax));
}

}  // namespace

std::string_view proceduralKindName(ProceduralKind kind) {
  for (const auto& [k, name] : kNames)
    if (k == kind) return name;
  return "unknown";
}

std::optional<ProceduralKind> parseProceduralKind(std::string_view name) {
  for (const auto& [kind, n] : kNames)
    if (n == name) return kind;
  return std::nullopt;
}

std::string proceduralSpecOf(const ProceduralField& field) {
  return std::string(kProceduralPrefix) + std::string(proceduralKindName(field.kind)) + ":" +
         std::to_string(field.size);
}

std::string proceduralKindNames() {
  std::string names;
  for (const auto& [kind, name] : kNames) {
    if (!names.empty()) names += ", ";
    names += name;
  }
  return names;
}

ProceduralField parseProceduralField(std::string_view nameAndSize) {
  const std::string usage = "expected procedural:NAME:SIZE with NAME one of " + proceduralKindNames() +
                            " and SIZE an integer in [1, " + std::to_string(kMaxProceduralSize) + "]";
  const size_t colon = nameAndSize.rfind(':');
  if (colon == std::string_view::npos)
    throw UsageError("procedural volume 'procedural:" + std::string(nameAndSize) + "': " + usage);
  const std::string_view name = nameAndSize.substr(0, colon);
  const std::string_view sizeText = nameAndSize.substr(colon + 1);
  const auto kind = parseProceduralKind(name);
  if (!kind)
    throw UsageError("procedural volume 'procedural:" + std::string(nameAndSize) + "': unknown name '" +
                     std::string(name) + "'; " + usage);
  uint64_t size = 0;
  const auto [end, ec] = std::from_chars(sizeText.data(), sizeText.data() + sizeText.size(), size);
  if (sizeText.empty() || ec != std::errc() || end != sizeText.data() + sizeText.size() || size < 1 ||
      size > kMaxProceduralSize)
    throw UsageError("procedural volume 'procedural:" + std::string(nameAndSize) + "': bad SIZE '" +
                     std::string(sizeText) + "'; " + usage);
  return {*kind, uint32_t(size)};
}

double proceduralValue(const ProceduralField& field, glm::dvec3 p) {
  p = clampToVolume(p, field.size);
  switch (field.kind) {
    case ProceduralKind::Sphere:
      return sphereValue(p, field.size);
    case ProceduralKind::Menger:
      return mengerValue(p, field.size);
    case ProceduralKind::Noise:
      return noiseValue(p, field.size);
    case ProceduralKind::MarschnerLobb:
      return marschnerLobbValue(p, field.size);
  }
  return 0.0;
}

uint8_t proceduralSample(const ProceduralField& field, uint32_t i, uint32_t j, uint32_t k) {
  const double v = proceduralValue(field, glm::dvec3(i, j, k) + 0.5);
  return uint8_t(std::clamp(std::lround(v), 0l, 255l));
}

ValueRange proceduralRange(const ProceduralField& field, const PositionBox& box) {
  const PositionBox clamped = clampToVolume(box, field.size);
  switch (field.kind) {
    case ProceduralKind::Sphere:
      return sphereRange(clamped, field.size);
    case ProceduralKind::Menger:
      return mengerRange(clamped, field.size);
    case ProceduralKind::Noise:
      return noiseRange(clamped, field.size);
    case ProceduralKind::MarschnerLobb:
      return marschnerLobbRange(clamped, field.size);
  }
  return {0.0, 255.0};
}

}  // namespace ropecast
