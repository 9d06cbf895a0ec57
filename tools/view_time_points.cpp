#include "tools/view_time_points.h"

#include <exception>
#include <utility>

namespace ropecast::tools {
namespace {

// Thrown through a conversion by its progress callback once the class stops.
struct Stopped {};

}  // namespace

TimePointStores::TimePointStores(uint32_t count, uint32_t shown, std::unique_ptr<BrickSource> shownSource,
                                 Convert convert, std::function<void()> ready)
    : count_(count), convert_(std::move(convert)), ready_(std::move(ready)) {
  made_[shown] = std::move(shownSource);
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
  return it == made_.end() ? nullptr : it->second.get();
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
    std::unique_ptr<BrickSource> source;
    std::optional<Failure> failure;
    try {
      source = convert_(t, [&](double fraction) {
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
    if (source) made_[t] = std::move(source);
    if (failure) failure_ = std::move(failure);
    lock.unlock();
    ready_();
    lock.lock();
  }
}

}  // namespace ropecast::tools
