#include "store/deflate_index.h"

#include <algorithm>
#include <list>

namespace ropecast {
namespace {

// Files whose indexes the registry keeps; each index holds at most kMaxPoints windows of 32 KiB (8 MiB).
constexpr size_t kIndexedFiles = 8;

struct IndexKey {
  FileIdentity file;
  uint64_t startOffset = 0;
  bool operator==(const IndexKey&) const = default;
};

}  // namespace

std::optional<DeflateAccessPoint> DeflateIndex::pointBefore(uint64_t output,
                                                            std::optional<uint64_t> past) const {
  std::lock_guard lock(mutex_);
  const auto after =
      std::upper_bound(points_.begin(), points_.end(), output,
                       [](uint64_t value, const DeflateAccessPoint& point) { return value < point.output; });
  if (after == points_.begin() || (past && std::prev(after)->output <= *past)) return std::nullopt;
  return *std::prev(after);
}

bool DeflateIndex::wantsPointAt(uint64_t output) const {
  std::lock_guard lock(mutex_);
  return points_.empty() ? output >= spacing_ : output >= points_.back().output + spacing_;
}

void DeflateIndex::add(DeflateAccessPoint point) {
  std::lock_guard lock(mutex_);
  if (points_.empty() ? point.output < spacing_ : point.output < points_.back().output + spacing_) return;
  points_.push_back(std::move(point));
  if (points_.size() <= kMaxPoints) return;
  // Thinned: every other point kept, so the points still span the stream, twice as far apart.
  std::vector<DeflateAccessPoint> kept;
  kept.reserve(points_.size() / 2 + 1);
  for (size_t i = 0; i < points_.size(); i += 2) kept.push_back(std::move(points_[i]));
  points_ = std::move(kept);
  spacing_ *= 2;
}

void DeflateIndex::memberChecked(uint64_t first, uint64_t end) {
  std::lock_guard lock(mutex_);
  if (std::ranges::find(checkedMembers_, std::pair(first, end)) == checkedMembers_.end())
    checkedMembers_.emplace_back(first, end);
}

bool DeflateIndex::memberCheckedAt(uint64_t output) const {
  std::lock_guard lock(mutex_);
  return std::ranges::any_of(
      checkedMembers_, [&](const auto& member) { return member.first <= output && output <= member.second; });
}

size_t DeflateIndex::pointCount() const {
  std::lock_guard lock(mutex_);
  return points_.size();
}

std::shared_ptr<DeflateIndex> deflateIndexFor(const PosixFile& file, uint64_t startOffset) {
  static std::mutex mutex;
  static std::list<std::pair<IndexKey, std::shared_ptr<DeflateIndex>>> recent;  // most recently asked first
  const IndexKey key{file.identity(), startOffset};
  std::lock_guard lock(mutex);
  const auto found =
      std::ranges::find(recent, key, &std::pair<IndexKey, std::shared_ptr<DeflateIndex>>::first);
  if (found != recent.end()) {
    recent.splice(recent.begin(), recent, found);
    return recent.front().second;
  }
  recent.emplace_front(key, std::make_shared<DeflateIndex>());
  if (recent.size() > kIndexedFiles) recent.pop_back();
  return recent.front().second;
}

}  // namespace ropecast
