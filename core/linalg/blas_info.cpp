#include "core/linalg/blas_info.hpp"

#include <dlfcn.h>

#include "core/common/thread_policy.hpp"

namespace wish::linalg {
namespace {

template <class Fn>
Fn lookup(const char* name) {
  return reinterpret_cast<Fn>(dlsym(RTLD_DEFAULT, name));
}

}  // namespace

BlasInfo blas_info() {
  BlasInfo info;
  using GetConfig = char* (*)();
  using GetThreads = int (*)();
  const auto get_config = lookup<GetConfig>("openblas_get_config");
  const auto get_threads = lookup<GetThreads>("openblas_get_num_threads");
  if (get_config) {
    info.openblas = true;
    info.name = "OpenBLAS";
    if (const char* text = get_config()) info.config = text;
  } else {
    info.name = "unknown (not OpenBLAS)";
  }
  if (get_threads) info.threads = get_threads();
  return info;
}

bool set_blas_threads(int threads) { return set_blas_thread_count(threads); }

std::string describe_blas() {
  const BlasInfo info = blas_info();
  std::string out = info.name;
  if (!info.config.empty()) out += " (" + info.config + ")";
  out += ", " + (info.threads < 0 ? std::string("?") : std::to_string(info.threads)) + " thread(s)";
  return out;
}

}  // namespace wish::linalg
