#include "server/cancel_registry.hpp"

namespace wish::server {

CancelRegistry::Registration::Registration(CancelRegistry& registry, Flag flag)
    : registry_(registry), flag_(std::move(flag)) {
  std::lock_guard lock(registry_.mutex_);
  if (registry_.cancelled_all_) flag_->store(true);
  registry_.flags_.insert(flag_);
}

CancelRegistry::Registration::~Registration() {
  std::lock_guard lock(registry_.mutex_);
  registry_.flags_.erase(flag_);
}

void CancelRegistry::cancel_all() {
  std::lock_guard lock(mutex_);
  cancelled_all_ = true;
  for (const auto& flag : flags_) flag->store(true);
}

std::size_t CancelRegistry::size() const {
  std::lock_guard lock(mutex_);
  return flags_.size();
}

}  // namespace wish::server
