// Test helpers: start tinyphong-server on a free loopback port as a subprocess, and small
// synchronous Beast clients with timeouts (every wait is bounded).
#pragma once
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <nlohmann/json.hpp>

namespace tpt {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = net::ip::tcp;
using namespace std::chrono_literals;

class ServerProcess {
 public:
  // stderr_path, when given, receives the server's stderr (a soak's thousands of expected
  // "websocket read: End of file" lines would otherwise flood the test's output).
  // max_files > 0 limits the server's open descriptors (RLIMIT_NOFILE), to run it out of them.
  explicit ServerProcess(std::vector<std::string> args, const std::string& stderr_path = "",
                         rlim_t max_files = 0) {
    int fds[2];
    if (pipe(fds) != 0) throw std::runtime_error("pipe");
    pid_ = fork();
    if (pid_ == 0) {
      dup2(fds[1], 1);
      close(fds[0]);
      if (max_files > 0) {
        const rlimit lim{max_files, max_files};
        setrlimit(RLIMIT_NOFILE, &lim);
      }
      if (!stderr_path.empty()) {
        const int err = open(stderr_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (err >= 0) dup2(err, 2);
      }
      // Under ASan, freed blocks sit in a 256 MiB quarantine, which would read as RSS growth
      // in the memory bound; keep it small (the option is ignored by non-ASan builds).
      std::string asan = getenv("ASAN_OPTIONS") ? getenv("ASAN_OPTIONS") : "";
      asan += (asan.empty() ? "" : ":") + std::string("quarantine_size_mb=4");
      setenv("ASAN_OPTIONS", asan.c_str(), 1);
      std::vector<std::string> all = {TP_SERVER_BINARY, "--port", "0"};
      all.insert(all.end(), args.begin(), args.end());
      std::vector<char*> argv;
      for (auto& a : all) argv.push_back(a.data());
      argv.push_back(nullptr);
      execv(argv[0], argv.data());
      _exit(127);
    }
    close(fds[1]);
    out_ = fds[0];
    // The first line says where it listens: "tinyphong: serving http://127.0.0.1:PORT/".
    std::string line;
    char c;
    while (read(out_, &c, 1) == 1 && c != '\n') line += c;
    const auto p = line.find("127.0.0.1:");
    if (p == std::string::npos) throw std::runtime_error("server did not start: " + line);
    port_ = static_cast<unsigned short>(std::stoi(line.substr(p + 10)));
  }
  ~ServerProcess() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
    close(out_);
  }
  unsigned short port() const { return port_; }
  pid_t pid() const { return pid_; }
  std::string host() const { return "127.0.0.1:" + std::to_string(port_); }
  long rss_kib() const {  // resident set size from /proc (Linux)
    std::ifstream f("/proc/" + std::to_string(pid_) + "/status");
    std::string k;
    long v = -1;
    while (f >> k)
      if (k == "VmRSS:") f >> v;
    return v;
  }
  // Open file descriptors, from /proc (Linux); -1 once the process is gone.
  int fd_count() const {
    std::error_code ec;
    int n = 0;
    for (std::filesystem::directory_iterator it("/proc/" + std::to_string(pid_) + "/fd", ec), end;
         !ec && it != end; it.increment(ec))
      ++n;
    return ec ? -1 : n;
  }
  // False once the process has ended (it is then reaped; exit_status() says how).
  bool running() {
    if (pid_ <= 0) return false;
    if (waitpid(pid_, &exit_status_, WNOHANG) != pid_) return true;
    pid_ = -1;
    return false;
  }
  int exit_status() const { return exit_status_; }
  // Sends sig and waits up to `limit`; returns the exit status or -1 on timeout.
  int signal_and_wait(int sig, std::chrono::milliseconds limit, std::chrono::milliseconds& took) {
    const auto t0 = std::chrono::steady_clock::now();
    kill(pid_, sig);
    int status = 0;
    while (std::chrono::steady_clock::now() - t0 < limit) {
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        took = std::chrono::duration_cast<std::chrono::milliseconds>(
            std::chrono::steady_clock::now() - t0);
        pid_ = -1;
        return status;
      }
      std::this_thread::sleep_for(5ms);
    }
    return -1;
  }

 private:
  pid_t pid_ = -1;
  int exit_status_ = 0;
  int out_ = -1;
  unsigned short port_ = 0;
};

struct Message {
  bool ok = false, binary = false;
  std::string data;
  beast::error_code ec;
};

class WsClient {
 public:
  // Throws on a failed handshake (e.g. 403) and when connect + handshake take longer than
  // timeout. rcvbuf > 0 shrinks the socket's receive buffer.
  WsClient(unsigned short port, std::string origin = "", std::string host = "", int rcvbuf = 0,
           std::chrono::milliseconds timeout = 10s)
      : ws_(ioc_), host_(host.empty() ? "127.0.0.1:" + std::to_string(port) : std::move(host)) {
    auto& sock = beast::get_lowest_layer(ws_);
    sock.open(tcp::v4());
    if (rcvbuf > 0) sock.set_option(net::socket_base::receive_buffer_size(rcvbuf));
    ws_.set_option(websocket::stream_base::decorator([origin](websocket::request_type& r) {
      if (!origin.empty()) r.set(http::field::origin, origin);
    }));
    ws_.read_message_max(64 << 20);
    bool done = false;
    beast::error_code ec;
    sock.async_connect({net::ip::make_address("127.0.0.1"), port}, [&](beast::error_code e) {
      if (e) {
        ec = e;
        done = true;
        return;
      }
      ws_.async_handshake(host_, "/ws", [&](beast::error_code h) {
        ec = h;
        done = true;
      });
    });
    finish(done, ec, timeout, "websocket handshake");
  }
  // A read that times out stays pending (the stream stays usable); the next call resumes it.
  Message read(std::chrono::milliseconds timeout = 10s) {
    Message m;
    if (!pending_) {
      pending_ = true;
      done_ = false;
      buf_.clear();
      ws_.async_read(buf_, [this](beast::error_code ec, std::size_t) {
        ec_ = ec;
        done_ = true;
      });
    }
    ioc_.restart();
    ioc_.run_for(timeout);
    if (!done_) {
      m.ec = net::error::timed_out;
      return m;
    }
    pending_ = false;
    m.ec = ec_;
    m.ok = !m.ec;
    m.binary = ws_.got_binary();
    m.data = beast::buffers_to_string(buf_.data());
    return m;
  }
  // Throws on an error and when the write takes longer than timeout.
  void send(const std::string& text, std::chrono::milliseconds timeout = 10s) {
    ws_.text(true);
    write(text, timeout);
  }
  void send_binary(const std::string& bytes, std::chrono::milliseconds timeout = 10s) {
    ws_.binary(true);
    write(bytes, timeout);
  }
  // Sends a close frame and waits up to timeout for the server's; false if it did not come.
  bool close(std::chrono::milliseconds timeout = 5s) {
    bool done = false;
    beast::error_code ec;
    ws_.async_close(websocket::close_code::normal, [&](beast::error_code e) {
      ec = e;
      done = true;
    });
    if (!run_until(done, timeout)) {
      abandon(done);
      return false;
    }
    return !ec;
  }
  void send_json(const nlohmann::json& j) { send(j.dump()); }
  // Reads until a text message of the given type (acking frames on the way, if asked).
  nlohmann::json read_json(const std::string& type, std::chrono::milliseconds timeout = 10s,
                           bool acks = true) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < end) {
      Message m = read(std::chrono::duration_cast<std::chrono::milliseconds>(
          end - std::chrono::steady_clock::now()));
      if (!m.ok) break;
      if (m.binary) {
        if (acks) ack(m.data);
        continue;
      }
      auto j = nlohmann::json::parse(m.data);
      if (j.value("type", "") == type) return j;
    }
    return nullptr;
  }
  void ack(const std::string& frame) {
    std::uint32_t id = 0;
    for (int i = 3; i >= 0; --i)
      id = (id << 8) | static_cast<std::uint8_t>(frame[8 + static_cast<std::size_t>(i)]);
    const bool ref = frame[6] == 1;
    send_json({{"type", "ack"}, {"id", id}, {"kind", ref ? "reference" : "device"}});
  }
  websocket::close_reason reason() const { return ws_.reason(); }
  websocket::stream<tcp::socket>& ws() { return ws_; }

 private:
  // Runs handlers until done is set or the time is up; an operation still pending then (e.g. a
  // timed-out read) keeps its state for the next call.
  bool run_until(const bool& done, std::chrono::milliseconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (!done && std::chrono::steady_clock::now() < end) {
      if (ioc_.stopped()) ioc_.restart();
      ioc_.run_one_until(end);
    }
    return done;
  }
  // An operation that timed out refers to its caller's locals: close the socket so that it
  // completes (operation_aborted) before those go away.
  void abandon(const bool& done) {
    beast::error_code ignored;
    beast::get_lowest_layer(ws_).close(ignored);
    run_until(done, 5s);
  }
  void write(const std::string& data, std::chrono::milliseconds timeout) {
    bool done = false;
    beast::error_code ec;
    ws_.async_write(net::buffer(data), [&](beast::error_code e, std::size_t) {
      ec = e;
      done = true;
    });
    finish(done, ec, timeout, "websocket write");
  }
  void finish(const bool& done, const beast::error_code& ec, std::chrono::milliseconds timeout,
              const char* what) {
    if (!run_until(done, timeout)) {
      abandon(done);
      throw boost::system::system_error(net::error::timed_out, what);
    }
    if (ec) throw boost::system::system_error(ec, what);
  }

  net::io_context ioc_;
  websocket::stream<tcp::socket> ws_;
  std::string host_;  // the handshake's Host, alive until the handshake completes
  beast::flat_buffer buf_;
  beast::error_code ec_;
  bool pending_ = false, done_ = false;
};

// One raw HTTP GET; returns the status code (0 on failure).
inline int http_get(unsigned short port, const std::string& target, const std::string& host = "") {
  net::io_context ioc;
  tcp::socket s(ioc);
  s.connect({net::ip::make_address("127.0.0.1"), port});
  http::request<http::empty_body> req{http::verb::get, target, 11};
  req.set(http::field::host, host.empty() ? "127.0.0.1:" + std::to_string(port) : host);
  http::write(s, req);
  beast::flat_buffer b;
  http::response<http::string_body> res;
  beast::error_code ec;
  http::read(s, b, res, ec);
  return ec ? 0 : res.result_int();
}

// Writes `request` on a fresh connection, then ends its sending side (the server reads an end of
// stream), and reads until the server closes the connection or `timeout` passes; returns what
// arrived (empty if the connection failed).
inline std::string raw_exchange(unsigned short port, const std::string& request,
                                std::chrono::milliseconds timeout = 5s) {
  net::io_context ioc;
  beast::tcp_stream s(ioc);
  beast::error_code ec;
  s.socket().connect({net::ip::make_address("127.0.0.1"), port}, ec);
  if (ec) return "";
  s.expires_after(timeout);
  std::string got;
  std::array<char, 4096> buf{};
  const auto read_more = [&](auto&& self) -> void {
    s.async_read_some(net::buffer(buf), [&](beast::error_code e, std::size_t n) {
      got.append(buf.data(), n);
      if (!e) self(self);
    });
  };
  net::async_write(s, net::buffer(request), [&](beast::error_code, std::size_t) {
    beast::error_code ignored;
    s.socket().shutdown(tcp::socket::shutdown_send, ignored);
  });
  read_more(read_more);
  ioc.run_for(timeout + 1s);
  return got;
}

}  // namespace tpt
