// The one place network errors are reported (Beast's examples' fail()): every session, the
// listener and the server's timers call it instead of dropping the error code silently.
#pragma once
#include <boost/beast/core/error.hpp>

namespace tp::server {

// Prints "what: message" to std::cerr, except for the codes that mean an orderly end: our own
// cancellation (operation_aborted), the peer's WebSocket close and the peer closing an HTTP
// connection between requests.
void fail(boost::beast::error_code ec, char const* what);

}  // namespace tp::server
