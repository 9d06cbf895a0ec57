#include "store/procedural_bricks.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include <glm/common.hpp>

#include "core/error.h"

namespace ropecast {

namespace {
uint8_t quantize(double v) {
  return uint8_t(std::clamp(std::lround(v), 0l, 255l));
}
}  // namespace

ProceduralBricks::ProceduralBricks(const ProceduralField& field, uint32_t brickSize, glm::dvec3 spacing)
    : field_(field) {
  if (field.size == 0) throw Error("ProceduralBricks: the field's size must be positive");
  try {
    info_.layout = OctreeLayout::forVolume(glm::u32vec3(field.size), brickSize);
  } catch (const std::invalid_argument& e) {
    throw Error(std::string("ProceduralBricks: ") + e.what());
  }
  info_.volume.dims = glm::u32vec3(field.size);
  info_.volume.spacing = spacing;
  info_.volume.type = SampleType::UInt8;
  info_.volume.valueMin = 0.0;
  info_.volume.valueMax = 255.0;
  info_.volume.description = proceduralSpecOf(field);
  info_.storedType = SampleType::UInt8;
  info_.mapping = {1.0, 0.0};
}

PositionBox ProceduralBricks::nodeBox(const NodeKey& key) const {
  const OctreeLayout& l = info_.layout;
  const double levelScale =
      std::ldexp(1.0, int(l.levelOfDepth(key.depth)));  // level-0 samples per level-L sample
  const glm::dvec3 first = glm::dvec3(key.coord) * double(l.brickSize) - double(kBrickBorder);
  const glm::dvec3 end = glm::dvec3(key.coord + 1u) * double(l.brickSize) + double(kBrickBorder);
  const glm::dvec3 size(field_.size);
  return {glm::clamp(first * levelScale, glm::dvec3(0.0), size),
          glm::clamp(end * levelScale, glm::dvec3(0.0), size)};
}

NodeInfo ProceduralBricks::node(const NodeKey& key) const {
  if (!info_.layout.isInside(key)) return {NodeKind::Outside, 0, 0};
  const ValueRange r = proceduralRange(field_, nodeBox(key));
  NodeInfo n;
  n.minValue = quantize(std::floor(r.min));
  n.maxValue = quantize(std::ceil(r.max));
  n.kind = n.minValue == n.maxValue ? NodeKind::Constant : NodeKind::Data;
  return n;
}

void ProceduralBricks::readBrick(const NodeKey& key, std::span<std::byte> out) const {
  const OctreeLayout& l = info_.layout;
  const uint32_t edge = l.storedBrickEdge();
  if (out.size() != brickBytes())
    throw Error("ProceduralBricks::readBrick: output has " + std::to_string(out.size()) +
                " bytes, expected " + std::to_string(brickBytes()));
  const NodeInfo n = node(key);
  if (n.kind != NodeKind::Data) {
    std::memset(out.data(), n.kind == NodeKind::Constant ? n.minValue : 0, out.size());
    return;
  }
  const uint32_t level = l.levelOfDepth(key.depth);
  const double levelScale = std::ldexp(1.0, int(level));
  const glm::u32vec3 levelDims = l.levelDims(level);
  // Level-L sample index of texel t along one axis, clamped to the level's dims (edge replication).
  const auto sampleCenter = [&](uint32_t coord, uint32_t t, uint32_t dim) {
    const int64_t g = int64_t(coord) * l.brickSize + int64_t(t) - int64_t(kBrickBorder);
    return (double(std::clamp<int64_t>(g, 0, int64_t(dim) - 1)) + 0.5) * levelScale;
  };
  auto* dst = reinterpret_cast<uint8_t*>(out.data());
  for (uint32_t z = 0; z < edge; ++z) {
    const double pz = sampleCenter(key.coord.z, z, levelDims.z);
    for (uint32_t y = 0; y < edge; ++y) {
      const double py = sampleCenter(key.coord.y, y, levelDims.y);
      for (uint32_t x = 0; x < edge; ++x)
        *dst++ = quantize(proceduralValue(field_, {sampleCenter(key.coord.x, x, levelDims.x), py, pz}));
    }
  }
}

std::unique_ptr<ProceduralBricks> openProceduralBricks(const std::string& spec, uint32_t brickSize) {
  return std::make_unique<ProceduralBricks>(parseProceduralField(proceduralNameAndSize(spec)), brickSize);
}

}  // namespace ropecast
