#pragma once
// `wish serve`: wires configuration, models, worker pool, HTTP front end and signals together and runs until
// SIGTERM / SIGINT; then drains (stop accepting, finish in-flight within the grace period) and returns 0.

#include "server/config.hpp"

namespace wish::server {

int run_server(ServerConfig config);

}  // namespace wish::server
