#include "tools/status_client/status_request.h"

#include <httplib.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <condition_variable>
#include <mutex>
#include <stop_token>
#include <thread>

namespace poet {
namespace {

using Clock = std::chrono::steady_clock;

// Stops a client's request once the deadline has passed. httplib's timeouts are per read, so only another thread
// can bound the whole answer: client.stop() shuts the socket down, which ends the read under way with an error.
// It is repeated until the request returns, because a stop() that comes while the socket is being connected
// finds no request in flight and has nothing to shut.
class Deadline {
 public:
  Deadline(httplib::Client& client, Clock::time_point at)
      : thread_([this, &client, at](std::stop_token stop) { watch(client, at, stop); }) {}
  ~Deadline() { thread_.request_stop(); }  // the jthread joins
  Deadline(const Deadline&) = delete;
  Deadline& operator=(const Deadline&) = delete;

  bool passed() const { return passed_; }

 private:
  void watch(httplib::Client& client, Clock::time_point at, const std::stop_token& stop) {
    std::mutex mutex;
    std::condition_variable_any wake;
    std::unique_lock lock(mutex);
    const auto never = [] { return false; };
    wake.wait_until(lock, stop, at, never);
    if (stop.stop_requested()) return;
    passed_ = true;
    while (!stop.stop_requested()) {
      client.stop();
      wake.wait_for(lock, stop, std::chrono::milliseconds(50), never);
    }
  }

  std::atomic<bool> passed_{false};
  std::jthread thread_;  // last: it starts once the flag exists, and is joined before the flag goes
};

// Why the answer was given up before httplib saw anything wrong with it.
enum class Refusal { kNone, kTooLarge, kBadLength };

// What one request saw besides httplib's result.
struct Exchange {
  bool headers_read = false;
  Refusal refusal = Refusal::kNone;
  std::string bad_length;  // the Content-Length that was not a number
  std::string content_type;
  std::string body;
};

// Checks an answer's headers before its body is read: a Content-Length that is not a number (httplib would read
// "-1" as 2^64 - 1 and "x" as 0) or that is larger than the cap is refused at once, before a byte of body.
bool headers_acceptable(const httplib::Response& response, size_t max_body_bytes, Exchange& exchange) {
  exchange.headers_read = true;
  exchange.content_type = response.get_header_value("Content-Type");
  if (!response.has_header("Content-Length")) return true;
  const std::string length = response.get_header_value("Content-Length");
  uint64_t declared = 0;
  const char* end = length.data() + length.size();
  const auto [ptr, ec] = std::from_chars(length.data(), end, declared);
  if ((ec != std::errc() && ec != std::errc::result_out_of_range) || ptr != end) {  // digits alone, at least one
    exchange.refusal = Refusal::kBadLength;
    exchange.bad_length = length.substr(0, 40);
    return false;
  }
  if (ec == std::errc::result_out_of_range || declared > max_body_bytes) {
    exchange.refusal = Refusal::kTooLarge;
    return false;
  }
  return true;
}

// Keeps a piece of the body, unless the body would outgrow the cap (a body without a Content-Length, or with
// chunks, has no size to check beforehand).
bool keep_body(const char* data, size_t size, size_t max_body_bytes, Exchange& exchange) {
  if (size > max_body_bytes - exchange.body.size()) {
    exchange.refusal = Refusal::kTooLarge;
    return false;
  }
  exchange.body.append(data, size);
  return true;
}

std::string megabytes(size_t bytes) { return std::to_string(bytes >> 20) + " MB"; }

// What went wrong with a request, for people.
std::string failure(httplib::Error error, const Exchange& exchange, bool deadline_passed, const StatusLimits& limits) {
  const auto seconds = std::chrono::duration_cast<std::chrono::seconds>(limits.deadline).count();
  if (deadline_passed)
    return "no complete answer within " + std::to_string(seconds) + " s (the limit for a whole answer)";
  switch (exchange.refusal) {
    case Refusal::kTooLarge:
      return "the answer is larger than " + megabytes(limits.max_body_bytes) + ", more than this request may take";
    case Refusal::kBadLength:
      return "a malformed answer: its Content-Length \"" + exchange.bad_length + "\" is not a number";
    case Refusal::kNone:
      break;
  }
  switch (error) {
    case httplib::Error::Connection:
    case httplib::Error::ConnectionTimeout:
      return "cannot reach the coordinator (nothing listens there, or no connection within " +
             std::to_string(kStatusConnectTimeoutS) + " s)";
    case httplib::Error::Read:
      // the read timeout is longer than the deadline, so a read that failed was not one that waited too long
      return exchange.headers_read
                 ? "a malformed answer: its body is cut short or not well-formed (its length or chunks)"
                 : "a malformed answer: no well-formed HTTP status line and headers (or the connection closed "
                   "before them)";
    case httplib::Error::Compression:
      return "a malformed answer: its compressed body cannot be decompressed";
    case httplib::Error::Write:
      return "the request could not be sent";
    default:
      return "request failed (" + httplib::to_string(error) + ")";
  }
}

}  // namespace

Expected<StatusAnswer> status_get(const HostPort& where, const std::string& path, const StatusLimits& limits) {
  httplib::Client client(where.host, where.port);
  client.set_connection_timeout(kStatusConnectTimeoutS, 0);
  // each read and write may take as long as the whole answer: the deadline decides, and says so
  const auto per_read = std::chrono::duration_cast<std::chrono::seconds>(limits.deadline) + std::chrono::seconds(1);
  client.set_read_timeout(per_read);
  client.set_write_timeout(per_read);
  Exchange exchange;
  bool deadline_passed = false;
  const httplib::Result result = [&] {
    const Deadline deadline(client, Clock::now() + limits.deadline);
    httplib::Result r = client.Get(
        path,
        [&](const httplib::Response& response) {
          return headers_acceptable(response, limits.max_body_bytes, exchange);
        },
        [&](const char* data, size_t size) { return keep_body(data, size, limits.max_body_bytes, exchange); });
    deadline_passed = deadline.passed();
    return r;
  }();
  if (!result) return Unexpected{failure(result.error(), exchange, deadline_passed, limits)};
  return StatusAnswer{result->status, std::move(exchange.content_type), std::move(exchange.body)};
}

}  // namespace poet
