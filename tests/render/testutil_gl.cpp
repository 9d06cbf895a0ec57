#include "tests/render/testutil_gl.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>

#include <gtest/gtest.h>

#include "render/backend_choice.h"

namespace ropecast::test {

GlContext& sharedGlContext() {
  static std::unique_ptr<GlContext> context = std::make_unique<GlContext>();
  return *context;
}

bool onHardwareGpu() {
  return !isSoftwareRenderer(sharedGlContext().info().renderer);
}

double psnrDb(const FloatImage& a, const FloatImage& b, uint32_t channels) {
  if (a.width != b.width || a.height != b.height || a.channels < channels || b.channels < channels)
    throw std::invalid_argument("psnrDb: images differ in size or channels");
  double sum = 0.0;
  const size_t n = size_t(a.width) * a.height;
  for (size_t p = 0; p < n; ++p)
    for (uint32_t c = 0; c < channels; ++c) {
      const double d = double(a.pixels[p * a.channels + c]) - double(b.pixels[p * b.channels + c]);
      sum += d * d;
    }
  const double mse = sum / double(n * channels);
  return mse == 0.0 ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(1.0 / mse);
}

double maxAbsDifference(const FloatImage& a, const FloatImage& b, uint32_t channels) {
  if (a.width != b.width || a.height != b.height || a.channels < channels || b.channels < channels)
    throw std::invalid_argument("maxAbsDifference: images differ in size or channels");
  double worst = 0.0;
  const size_t n = size_t(a.width) * a.height;
  for (size_t p = 0; p < n; ++p)
    for (uint32_t c = 0; c < channels; ++c) {
      const float x = a.pixels[p * a.channels + c], y = b.pixels[p * b.channels + c];
      if (x == y) continue;  // also inf == inf
      const double d = std::abs(double(x) - double(y));
      worst = std::isnan(d) ? std::numeric_limits<double>::infinity() : std::max(worst, d);
    }
  return worst;
}

namespace {

std::vector<std::byte> makeBrick(const SceneSpec& spec, const OctreeLayout& layout, const NodeKey& node) {
  const uint32_t level = layout.levelOfDepth(node.depth);
  const glm::u32vec3 levelDims = layout.levelDims(level);
  const uint32_t e = layout.storedBrickEdge();
  const double storedMax = spec.storedType == SampleType::UInt8 ? 255.0 : 65535.0;
  const glm::dvec3 cell = spec.spacing * std::ldexp(1.0, int(level));
  std::vector<std::byte> bytes(size_t(e) * e * e * bytesPerSample(spec.storedType));
  for (uint32_t k = 0; k < e; ++k)
    for (uint32_t j = 0; j < e; ++j)
      for (uint32_t i = 0; i < e; ++i) {
        glm::dvec3 n;
        for (int a = 0; a < 3; ++a) {
          const int64_t idx = int64_t(node.coord[a]) * layout.brickSize + int64_t(glm::u32vec3(i, j, k)[a]) -
                              int64_t(kBrickBorder);
          n[a] = double(std::clamp<int64_t>(idx, 0, int64_t(levelDims[a]) - 1));
        }
        const double v = std::clamp(spec.value((n + 0.5) * cell), 0.0, 1.0);
        const size_t at = i + size_t(e) * (j + size_t(e) * k);
        if (spec.storedType == SampleType::UInt8) {
          const uint8_t q = uint8_t(std::lround(v * storedMax));
          std::memcpy(&bytes[at], &q, 1);
        } else {
          const uint16_t q = uint16_t(std::lround(v * storedMax));
          std::memcpy(&bytes[at * 2], &q, 2);
        }
      }
  return bytes;
}

}  // namespace

GlScene buildScene(const SceneSpec& spec) {
  GlContext& ctx = sharedGlContext();
  GlScene scene;
  const OctreeLayout layout = OctreeLayout::forVolume(spec.dims, spec.brickSize);
  scene.info.layout = layout;
  scene.info.volume.dims = spec.dims;
  scene.info.volume.spacing = spec.spacing;
  scene.info.volume.type = spec.storedType;
  scene.info.storedType = spec.storedType;
  scene.geometry = VolumeGeometry::of(scene.info);

  std::vector<NodeKey> leaves;
  std::function<void(const NodeKey&)> visit = [&](const NodeKey& node) {
    const bool inside = layout.isInside(node);
    if (inside && node.depth < layout.maxDepth && (!spec.refine || spec.refine(node))) {
      for (uint32_t o = 0; o < 8; ++o) visit(node.child(o));
      return;
    }
    leaves.push_back(node);
  };
  visit(NodeKey{});

  size_t dataCount = 0;
  for (const NodeKey& k : leaves)
    if (layout.isInside(k) && !(spec.emptyLeaf && spec.emptyLeaf(k))) ++dataCount;
  const uint64_t slotBytes = uint64_t(layout.storedBrickSamples()) * bytesPerSample(spec.storedType);
  scene.pool =
      std::make_unique<BrickPool>(BrickPoolConfig{spec.brickSize, spec.storedType,
                                                  std::max<uint64_t>(dataCount, 1) * slotBytes * 2, false},
                                  ctx.info().max3DTextureSize);
  scene.minLeafDepth = layout.maxDepth;
  const double storedMax = storedMaxOf(spec.storedType);
  for (const NodeKey& k : leaves) {
    CutLeaf leaf{k.depth, k.coord, LeafKind::Empty, 0};
    float leafMax = -1.0f, leafMin = 2.0f;
    if (layout.isInside(k) && !(spec.emptyLeaf && spec.emptyLeaf(k))) {
      const uint32_t slot = uint32_t(scene.bricks.size());
      if (slot >= scene.pool->slotCount()) throw std::runtime_error("buildScene: pool too small");
      std::vector<std::byte> brick = makeBrick(spec, layout, k);
      uint32_t largest = 0, smallest = UINT32_MAX;
      for (size_t i = 0; i < layout.storedBrickSamples(); ++i) {
        uint16_t v = 0;
        if (spec.storedType == SampleType::UInt8)
          v = uint16_t(brick[i]);
        else
          std::memcpy(&v, &brick[2 * i], 2);
        largest = std::max<uint32_t>(largest, v);
        smallest = std::min<uint32_t>(smallest, v);
      }
      if (spec.solidAbove && double(smallest) / storedMax > *spec.solidAbove) {
        leaf.kind = LeafKind::Solid;
        ++scene.solidLeaves;
        scene.cut.leaves.push_back(leaf);
        scene.leafMaxima.push_back(leafMax);
        scene.leafMinima.push_back(leafMin);
        continue;
      }
      leaf.kind = LeafKind::Data;
      leaf.brickSlot = slot;
      leafMax = float(largest / storedMax);
      leafMin = float(smallest / storedMax);
      scene.pool->upload(slot, brick);
      scene.bricks.emplace(slot, std::move(brick));
      ++scene.dataLeaves;
      scene.minLeafDepth = std::min(scene.minLeafDepth, k.depth);
      scene.maxLeafDepth = std::max(scene.maxLeafDepth, k.depth);
    }
    scene.cut.leaves.push_back(leaf);
    scene.leafMaxima.push_back(leafMax);
    scene.leafMinima.push_back(leafMin);
  }
  scene.gradients = std::make_unique<GradientPool>(scene.pool->geometry().textureDims);
  std::vector<glm::u32vec3> origins;
  for (const auto& [slot, brick] : scene.bricks) origins.push_back(scene.pool->geometry().slotOrigin(slot));
  scene.gradients->derive(scene.pool->texture(), origins, glm::u32vec3(scene.pool->geometry().slotEdge));
  scene.index = buildRopeIndex(scene.cut);
  scene.indexTexture = std::make_unique<IndexTexture>(4, ctx.info().maxTextureBufferTexels);
  scene.indexTexture->upload(std::span<const uint32_t>(
      reinterpret_cast<const uint32_t*>(scene.index.texels.data()), scene.index.texels.size() * 4));
  return scene;
}

std::vector<float> GlScene::leafBounds(RenderMode mode) const {
  if (mode == RenderMode::Mip) return leafMaxima;
  std::vector<float> bounds;
  if (mode == RenderMode::MinIp)
    for (float v : leafMinima) bounds.push_back(-v);
  return bounds;
}

CpuRenderInput cpuInputOf(const RaycastFrame& frame) {
  CpuRenderInput input;
  input.camera = frame.camera;
  input.width = frame.width;
  input.height = frame.height;
  input.params = frame.params;
  input.tf = frame.tf;
  input.leafMaxima = frame.leafMaxima;
  return input;
}

void renderScene(RaycastPass& pass, const GlScene& scene, RaycastFrame frame, const TileSchedule& schedule) {
  frame.pool = scene.pool.get();
  frame.gradients = scene.gradients.get();
  frame.index = scene.indexTexture.get();
  frame.volume = scene.geometry;
  pass.render(frame, schedule);
}

}  // namespace ropecast::test
