#include "tools/view_series.h"

#include <exception>
#include <utility>
#include <vector>

namespace ropecast::tools {
namespace {

// Thrown through a conversion by its progress callback once the class stops.
struct Stopped {};

}  // namespace

SeriesStores::SeriesStores(uint32_t count, uint32_t shown, Made shownSource, uint64_t keepBytes,
                           Convert convert, std::function<void()> ready)
    : count_(count), convert_(std::move(convert)), ready_(std::move(ready)), keepBytes_(keepBytes) {
  made_[shown] = Kept{std::move(shownSource), ++shows_};
  thread_ = std::thread([this] { work(); });
}

SeriesStores::~SeriesStores() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void SeriesStores::ask(uint32_t v) {
  {
    std::lock_guard lock(mutex_);
    if (v >= count_ || made_.count(v) || (inFlight_ && inFlight_->volume == v)) return;
    queued_ = v;
  }
  wake_.notify_all();
}

BrickSource* SeriesStores::find(uint32_t v) const {
  std::lock_guard lock(mutex_);
  const auto it = made_.find(v);
  return it == made_.end() ? nullptr : it->second.made.source.get();
}

void SeriesStores::shown(uint32_t v) {
  std::vector<Made> dropped;  // closed outside the lock
  {
    std::lock_guard lock(mutex_);
    const auto it = made_.find(v);
    if (it == made_.end()) return;
    it->second.lastShown = ++shows_;
    uint64_t bytes = 0;
    for (const auto& [volume, kept] : made_) bytes += kept.made.bytes;
    while (bytes > keepBytes_) {
      auto oldest = made_.end();
      for (auto k = made_.begin(); k != made_.end(); ++k)
        if (k->first != v && (oldest == made_.end() || k->second.lastShown < oldest->second.lastShown))
          oldest = k;
      if (oldest == made_.end()) break;
      bytes -= oldest->second.made.bytes;
      dropped.push_back(std::move(oldest->second.made));
      made_.erase(oldest);
    }
  }
}

size_t SeriesStores::keptCount() const {
  std::lock_guard lock(mutex_);
  return made_.size();
}

uint64_t SeriesStores::keptBytes() const {
  std::lock_guard lock(mutex_);
  uint64_t bytes = 0;
  for (const auto& [volume, kept] : made_) bytes += kept.made.bytes;
  return bytes;
}

std::optional<SeriesStores::Converting> SeriesStores::converting() const {
  std::lock_guard lock(mutex_);
  return inFlight_;
}

std::optional<SeriesStores::Failure> SeriesStores::takeFailure() {
  std::lock_guard lock(mutex_);
  return std::exchange(failure_, std::nullopt);
}

void SeriesStores::work() {
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [&] { return stopping_ || queued_; });
    if (stopping_) return;
    const uint32_t v = *std::exchange(queued_, std::nullopt);
    inFlight_ = Converting{v, 0.0};
    lock.unlock();
    Made made;
    std::optional<Failure> failure;
    try {
      made = convert_(v, [&](double fraction) {
        std::lock_guard progressLock(mutex_);
        if (stopping_) throw Stopped{};
        inFlight_->fraction = fraction;
      });
    } catch (const Stopped&) {
      return;
    } catch (const std::exception& e) {
      failure = Failure{v, e.what()};
    }
    lock.lock();
    inFlight_.reset();
    if (made.source) made_[v] = Kept{std::move(made), 0};
    if (failure) failure_ = std::move(failure);
    lock.unlock();
    ready_();
    lock.lock();
  }
}

}  // namespace ropecast::tools
