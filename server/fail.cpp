#include "server/fail.hpp"

#include <iostream>
#include <string>

#include <boost/asio/error.hpp>
#include <boost/beast/http/error.hpp>
#include <boost/beast/websocket/error.hpp>

namespace tp::server {

void fail(boost::beast::error_code ec, char const* what) {
  if (!ec || ec == boost::asio::error::operation_aborted ||
      ec == boost::beast::websocket::error::closed ||
      ec == boost::beast::http::error::end_of_stream)
    return;
  // One write per line: with several I/O threads, lines from different sessions do not mix.
  std::cerr << (std::string(what) + ": " + ec.message() + "\n");
}

}  // namespace tp::server
