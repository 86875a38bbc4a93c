#pragma once
// SIGHUP, SIGTERM and SIGINT are blocked from the very start of the process, before the shared libraries'
// constructors run (OpenBLAS starts its thread pool in one), so that every thread of the process blocks them and
// `wish serve` can take them in one thread with sigwait (server/signals.hpp). Commands that do not take signals
// themselves restore the default mask before they run: Ctrl-C stops them as usual.

namespace wish::cli {

void unblock_process_signals();

}  // namespace wish::cli
