#include "server/work_backlog.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <queue>
#include <vector>

namespace wish::server {

namespace {
// The size measure the cost grows with (work_backlog.hpp): MB^1.25.
double size_measure(std::uint64_t bytes) { return std::pow(std::max<double>(1.0, static_cast<double>(bytes)) / 1e6, 1.25); }
// Weight of the newest completed job in the learned rate: the last few jobs dominate, so the rate follows a change
// of load within a handful of jobs.
constexpr double kLearningWeight = 0.3;
}  // namespace

WorkBacklog::Ticket::~Ticket() {
  std::lock_guard lock(backlog_->mutex_);
  backlog_->items_.erase(id_);
}

void WorkBacklog::Ticket::set_bytes(std::optional<std::uint64_t> bytes) {
  std::lock_guard lock(backlog_->mutex_);
  backlog_->items_[id_].bytes = bytes;
}

void WorkBacklog::Ticket::start() {
  std::lock_guard lock(backlog_->mutex_);
  auto& item = backlog_->items_[id_];
  item.running = true;
  item.started = Clock::now();
}

std::optional<double> WorkBacklog::predict(std::uint64_t bytes) const {
  std::lock_guard lock(mutex_);
  if (!rate_) return std::nullopt;
  return *rate_ * size_measure(bytes);
}

void WorkBacklog::learn(std::uint64_t bytes, double seconds) {
  if (!(seconds > 0) || !std::isfinite(seconds)) return;
  const double sample = seconds / size_measure(bytes);
  std::lock_guard lock(mutex_);
  rate_ = rate_ ? (1 - kLearningWeight) * *rate_ + kLearningWeight * sample : sample;
}

double WorkBacklog::wait_seconds() const {
  std::lock_guard lock(mutex_);
  const auto now = Clock::now();
  const auto seconds = [this](const Item& item) {
    return rate_ && item.bytes ? *rate_ * size_measure(*item.bytes) : 0.0;
  };
  // When each worker is next free (a min-heap), then the waiting jobs in admission order, each on the first free one.
  std::vector<double> free_at;
  for (const auto& [id, item] : items_)
    if (item.running && static_cast<int>(free_at.size()) < workers_)
      free_at.push_back(std::max(0.0, seconds(item) - std::chrono::duration<double>(now - item.started).count()));
  free_at.resize(static_cast<std::size_t>(workers_), 0.0);
  std::priority_queue<double, std::vector<double>, std::greater<>> heap(free_at.begin(), free_at.end());
  for (const auto& [id, item] : items_) {
    if (item.running) continue;
    const double t = heap.top();
    heap.pop();
    heap.push(t + seconds(item));
  }
  return heap.top();
}

std::shared_ptr<WorkBacklog::Ticket> WorkBacklog::enter(std::optional<std::uint64_t> bytes) {
  std::lock_guard lock(mutex_);
  const std::uint64_t id = next_id_++;
  items_[id].bytes = bytes;
  return std::shared_ptr<Ticket>(new Ticket(shared_from_this(), id));
}

std::size_t WorkBacklog::size() const {
  std::lock_guard lock(mutex_);
  return items_.size();
}

}  // namespace wish::server
