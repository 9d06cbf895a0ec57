#include "tools/view_time_points.h"

#include <exception>
#include <utility>
#include <vector>

namespace ropecast::tools {
namespace {

// Thrown through a conversion by its progress callback once the class stops.
struct Stopped {};

}  // namespace

TimePointStores::TimePointStores(uint32_t count, uint32_t shown, Made shownSource, uint64_t keepBytes,
                                 Convert convert, std::function<void()> ready)
    : count_(count), convert_(std::move(convert)), ready_(std::move(ready)), keepBytes_(keepBytes) {
  made_[shown] = Kept{std::move(shownSource), ++shows_};
  thread_ = std::thread([this] { work(); });
}

TimePointStores::~TimePointStores() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void TimePointStores::ask(uint32_t t) {
  {
    std::lock_guard lock(mutex_);
    if (t >= count_ || made_.count(t) || (inFlight_ && inFlight_->timePoint == t)) return;
    queued_ = t;
  }
  wake_.notify_all();
}

BrickSource* TimePointStores::find(uint32_t t) const {
  std::lock_guard lock(mutex_);
  const auto it = made_.find(t);
  return it == made_.end() ? nullptr : it->second.made.source.get();
}

void TimePointStores::shown(uint32_t t) {
  std::vector<Made> dropped;  // closed outside the lock
  {
    std::lock_guard lock(mutex_);
    const auto it = made_.find(t);
    if (it == made_.end()) return;
    it->second.lastShown = ++shows_;
    uint64_t bytes = 0;
    for (const auto& [time, kept] : made_) bytes += kept.made.bytes;
    while (bytes > keepBytes_) {
      auto oldest = made_.end();
      for (auto k = made_.begin(); k != made_.end(); ++k)
        if (k->first != t && (oldest == made_.end() || k->second.lastShown < oldest->second.lastShown))
          oldest = k;
      if (oldest == made_.end()) break;
      bytes -= oldest->second.made.bytes;
      dropped.push_back(std::move(oldest->second.made));
      made_.erase(oldest);
    }
  }
}

size_t TimePointStores::keptCount() const {
  std::lock_guard lock(mutex_);
  return made_.size();
}

uint64_t TimePointStores::keptBytes() const {
  std::lock_guard lock(mutex_);
  uint64_t bytes = 0;
  for (const auto& [time, kept] : made_) bytes += kept.made.bytes;
  return bytes;
}

std::optional<TimePointStores::Converting> TimePointStores::converting() const {
  std::lock_guard lock(mutex_);
  return inFlight_;
}

std::optional<TimePointStores::Failure> TimePointStores::takeFailure() {
  std::lock_guard lock(mutex_);
  return std::exchange(failure_, std::nullopt);
}

void TimePointStores::work() {
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [&] { return stopping_ || queued_; });
    if (stopping_) return;
    const uint32_t t = *std::exchange(queued_, std::nullopt);
    inFlight_ = Converting{t, 0.0};
    lock.unlock();
    Made made;
    std::optional<Failure> failure;
    try {
      made = convert_(t, [&](double fraction) {
        std::lock_guard progressLock(mutex_);
        if (stopping_) throw Stopped{};
        inFlight_->fraction = fraction;
      });
    } catch (const Stopped&) {
      return;
    } catch (const std::exception& e) {
      failure = Failure{t, e.what()};
    }
    lock.lock();
    inFlight_.reset();
    if (made.source) made_[t] = Kept{std::move(made), 0};
    if (failure) failure_ = std::move(failure);
    lock.unlock();
    ready_();
    lock.lock();
  }
}

}  // namespace ropecast::tools
