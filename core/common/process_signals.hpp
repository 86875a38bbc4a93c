#pragma once
// SIGHUP, SIGTERM and SIGINT are blocked from the very start of the process, before the shared libraries'
// constructors run (OpenBLAS starts its thread pool in one), so that every thread of the process blocks them and
// the service can take them in one thread with sigwait (server/signals.hpp). This is done by a .preinit_array entry
// in process_signals.cpp; it is in effect in every executable that links this object, i.e. that calls one of the
// functions below (a static library's object is linked only when referenced). The mask survives exec, so
// `wish serve` handing over to `wish-server` keeps it too.
// Commands that do not take signals themselves restore the default mask before they run: Ctrl-C stops them as usual.

namespace wish {

void unblock_process_signals();
// True when all three signals are blocked in the calling thread (what the service checks before it starts threads).
bool process_signals_blocked();

}  // namespace wish
