#include "coordinator/status/status_server.h"

#include <arpa/inet.h>
#include <microhttpd.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <exception>
#include <mutex>
#include <unordered_map>

#include "common/text/utf8.h"
#include "coordinator/status/status_routes.h"

namespace poet {
namespace {

// Connections shed but not yet closed by their loop: libmicrohttpd's own limits are the caps plus these, so that it
// never refuses the new connection a shedding makes room for.
constexpr size_t kSheddingInFlight = 64;

// One request's state between libmicrohttpd's calls: what its URI was found to be, how much body has come.
struct RequestState {
  int refusal = 0;  // 414 or 400 when the URI is refused before libmicrohttpd reads its query, else 0
  bool headers_in = false;
  size_t body_bytes = 0;
};

// libmicrohttpd's URI log callback, which sees the request's URI before libmicrohttpd parses its query: its
// return is the request's state. libmicrohttpd 0.9.75 (Debian 12's) keeps each query parameter in the
// connection's 32 KB memory pool, and when a query of a few hundred parameters fills the pool it closes the
// connection without an answer. So a URI to be refused, too long or with too many parameters, has its query
// ended here, in libmicrohttpd's own buffer of the request line (the callback's `const` is only the API's: the
// same bytes are parsed in place right after), and access() answers with the refusal: libmicrohttpd parses
// nothing of it. The query is found with strchr: a URI with a NUL byte before its '?' hides its query from this
// check (as from the routes), and such a request, not text, may still be closed unanswered.
void* screen_uri(void*, const char* uri, MHD_Connection*) {
  auto* state = new RequestState;
  if (uri == nullptr) return state;  // a request line without a URI
  const size_t length = std::strlen(uri);
  const char* query = std::strchr(uri, '?');
  const size_t params = query == nullptr ? 0 : 1 + static_cast<size_t>(std::count(query, uri + length, '&'));
  if (length > kMaxUriBytes) {
    state->refusal = 414;
  } else if (params > kMaxQueryParams) {
    state->refusal = 400;
  }
  if (state->refusal != 0 && query != nullptr) const_cast<char*>(query)[1] = '\0';
  return state;
}

MHD_Result queue(MHD_Connection* connection, const StatusResponse& r) {
  MHD_Response* response =
      MHD_create_response_from_buffer(r.body.size(), const_cast<char*>(r.body.data()), MHD_RESPMEM_MUST_COPY);
  if (response == nullptr) return MHD_NO;
  MHD_add_response_header(response, MHD_HTTP_HEADER_CONTENT_TYPE, r.content_type.c_str());
  MHD_add_response_header(response, MHD_HTTP_HEADER_CACHE_CONTROL, "no-store");
  if (!r.allow.empty()) MHD_add_response_header(response, MHD_HTTP_HEADER_ALLOW, r.allow.c_str());
  const MHD_Result queued = MHD_queue_response(connection, static_cast<unsigned>(r.status), response);
  MHD_destroy_response(response);
  return queued;
}

MHD_Result add_query_param(void* params, MHD_ValueKind, const char* key, const char* value) {
  static_cast<QueryParams*>(params)->emplace(key, value == nullptr ? "" : value);
  return MHD_YES;
}

void request_completed(void*, MHD_Connection*, void** state, MHD_RequestTerminationCode) {
  delete static_cast<RequestState*>(*state);
  *state = nullptr;
}

// The client's address without its port (IPv4, or IPv6 as libmicrohttpd gives it), the shedder's key.
std::string client_address(MHD_Connection* connection) {
  const MHD_ConnectionInfo* info = MHD_get_connection_info(connection, MHD_CONNECTION_INFO_CLIENT_ADDRESS);
  if (info == nullptr || info->client_addr == nullptr) return "";
  char text[INET6_ADDRSTRLEN] = "";
  const sockaddr* address = info->client_addr;
  if (address->sa_family == AF_INET) {
    ::inet_ntop(AF_INET, &reinterpret_cast<const sockaddr_in*>(address)->sin_addr, text, sizeof text);
  } else if (address->sa_family == AF_INET6) {
    ::inet_ntop(AF_INET6, &reinterpret_cast<const sockaddr_in6*>(address)->sin6_addr, text, sizeof text);
  }
  return text;
}

}  // namespace

struct StatusServer::Impl {
  StatusBoard& board;
  StatusServerOptions options;
  MHD_Daemon* daemon = nullptr;
  // the connections held, by the loops' threads: who came when from where, and each one's socket
  std::mutex connections_lock;
  ConnectionShedder shedder{options.caps};
  std::unordered_map<ConnectionShedder::Id, int> sockets;

  StatusResponse respond(const std::string& method, const std::string& path, const QueryParams& query) const {
    try {
      if (options.health_only && path != "/healthz")
        return error_response(404,
                              "this listener answers /healthz only; the rest is on the status socket "
                              "(--status-address)");
      return status_response(board, method, path, query);
    } catch (const std::exception&) {
      return error_response(500, "internal error");
    }
  }

  // libmicrohttpd's access handler: called once the headers are in, then for each piece of body, then with none.
  static MHD_Result access(void* self, MHD_Connection* connection, const char* url, const char* method, const char*,
                           const char*, size_t* upload_data_size, void** state) {
    const Impl& impl = *static_cast<const Impl*>(self);
    // screen_uri made the state: libmicrohttpd calls it once for every request, before this handler
    auto& request = *static_cast<RequestState*>(*state);
    if (!request.headers_in) {
      request.headers_in = true;
      if (request.refusal == 414)
        return queue(connection,
                     error_response(414, "request URI too long (at most " + std::to_string(kMaxUriBytes) + " bytes)"));
      if (request.refusal == 400)
        return queue(connection, error_response(400, "too many query parameters (at most " +
                                                         std::to_string(kMaxQueryParams) + ")"));
      const char* length = MHD_lookup_connection_value(connection, MHD_HEADER_KIND, MHD_HTTP_HEADER_CONTENT_LENGTH);
      size_t declared = 0;
      if (length != nullptr) {
        const auto [end, error] = std::from_chars(length, length + std::strlen(length), declared);
        if (error != std::errc() || declared > impl.options.payload_max_bytes)
          return queue(connection, error_response(413, "request body too large"));
      }
      return MHD_YES;
    }
    if (*upload_data_size > 0) {  // the body: only counted, no route reads one
      request.body_bytes += *upload_data_size;
      *upload_data_size = 0;
      // a body without a declared length that outgrows the limit: libmicrohttpd cannot answer while it reads a
      // body, so the connection is closed (one with a length beyond the limit got its 413 at once, above)
      return request.body_bytes > impl.options.payload_max_bytes ? MHD_NO : MHD_YES;
    }
    QueryParams query;
    MHD_get_connection_values(connection, MHD_GET_ARGUMENT_KIND, add_query_param, &query);
    return queue(connection, impl.respond(method, url, query));
  }

  // libmicrohttpd's connection callback, on the loop that took or closes the connection: a new one may shed an old
  // one. libmicrohttpd 0.9.75 has no call to close a connection from outside its loop, so the shed one's socket is
  // shut down here and its loop, woken by the end of input, closes it. It is still open: libmicrohttpd calls back
  // on a close (which takes this lock) before it closes the socket.
  static void notify(void* self, MHD_Connection* connection, void** context, MHD_ConnectionNotificationCode code) {
    Impl& impl = *static_cast<Impl*>(self);
    const std::lock_guard lock(impl.connections_lock);
    if (code == MHD_CONNECTION_NOTIFY_CLOSED) {
      const auto id = static_cast<ConnectionShedder::Id>(reinterpret_cast<uintptr_t>(*context));
      impl.shedder.close(id);
      impl.sockets.erase(id);
      return;
    }
    const MHD_ConnectionInfo* fd = MHD_get_connection_info(connection, MHD_CONNECTION_INFO_CONNECTION_FD);
    if (fd == nullptr) return;  // not tracked (its context stays 0)
    const ConnectionShedder::Admission admission = impl.shedder.open(client_address(connection));
    impl.sockets.emplace(admission.id, fd->connect_fd);
    *context = reinterpret_cast<void*>(static_cast<uintptr_t>(admission.id));
    if (admission.shed) ::shutdown(impl.sockets.at(*admission.shed), SHUT_RDWR);
  }
};

StatusServerOptions health_listener_options() {
  StatusServerOptions options;
  options.threads = 2;  // a probe, and one slow answer
  options.idle_timeout = std::chrono::seconds(1);
  options.health_only = true;
  options.caps = {.total = 256, .per_address = 64};  // probes are few; a crowd here only sheds its own
  return options;
}

size_t descriptors_needed(const StatusServerOptions& options) {
  const size_t threads = static_cast<size_t>(std::clamp(options.threads, 1, 16));
  return options.caps.total + kSheddingInFlight + 1 + 2 * threads;  // each loop: an epoll and an eventfd
}

bool fit_listeners(uint64_t descriptor_limit, StatusServerOptions& status, StatusServerOptions& health) {
  const uint64_t share = descriptor_limit / 2;
  const uint64_t needed = descriptors_needed(status) + descriptors_needed(health);
  if (needed <= share) return false;
  // the caps' part of what each needs shrinks; the rest (shedding in flight, sockets of its own) is fixed
  const uint64_t caps = status.caps.total + health.caps.total;
  const uint64_t fixed = needed - caps;
  const uint64_t room = share > fixed ? share - fixed : 0;
  for (StatusServerOptions* options : {&status, &health}) {
    ConnectionCaps& c = options->caps;
    const size_t total = std::max<size_t>(1, static_cast<size_t>(c.total * room / caps));
    c.per_address = std::max<size_t>(1, c.per_address * total / c.total);
    c.total = total;
  }
  return true;
}

StatusServer::StatusServer(StatusBoard& board, StatusServerOptions options) : board_(board), options_(options) {}

StatusServer::~StatusServer() { stop(); }

Expected<int> StatusServer::start(const std::string& address) {
  if (impl_) return Unexpected{"status socket: already serving on port " + std::to_string(port_)};
  const Expected<HostPort> where = parse_host_port(address);
  if (!where) return Unexpected{"status socket: " + where.error()};
  const std::string cannot = "status socket " + valid_utf8(address) +
                             ": cannot listen (the port is in use, or the host is not an address of this machine)";

  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE;
  addrinfo* found = nullptr;
  const std::string port_text = std::to_string(where->port);
  if (::getaddrinfo(where->host.c_str(), port_text.c_str(), &hints, &found) != 0 || found == nullptr)
    return Unexpected{cannot};
  sockaddr_storage bind_address{};
  std::memcpy(&bind_address, found->ai_addr, std::min<size_t>(found->ai_addrlen, sizeof bind_address));
  const bool ipv6 = found->ai_family == AF_INET6;
  ::freeaddrinfo(found);

  auto impl = std::make_unique<Impl>(board_, options_);
  // Event-driven (epoll, a few threads each with its own loop): a connection that trickles its request costs a
  // slot and a buffer, not a thread, so slow clients cannot hold the others' answers; an idle one is closed after
  // the idle timeout, and the shedder keeps room for new ones. SO_REUSEADDR (libmicrohttpd's default) but not
  // SO_REUSEPORT, with which a second coordinator could bind the same port; MSG_NOSIGNAL, so a client that hangs up
  // cannot raise SIGPIPE.
  const auto timeout_s = static_cast<unsigned>(std::max<int64_t>(1, options_.idle_timeout.count()));
  const unsigned threads = static_cast<unsigned>(std::clamp(options_.threads, 1, 16));
  const auto connection_limit = static_cast<unsigned>(impl->options.caps.total + kSheddingInFlight);
  const auto address_limit = static_cast<unsigned>(impl->options.caps.per_address + kSheddingInFlight);
  unsigned flags = MHD_USE_INTERNAL_POLLING_THREAD | MHD_USE_EPOLL;
  if (ipv6) flags |= MHD_USE_IPv6;
  impl->daemon = MHD_start_daemon(
      flags, static_cast<uint16_t>(where->port), nullptr, nullptr, &Impl::access, impl.get(), MHD_OPTION_SOCK_ADDR,
      reinterpret_cast<sockaddr*>(&bind_address), MHD_OPTION_THREAD_POOL_SIZE, threads, MHD_OPTION_CONNECTION_TIMEOUT,
      timeout_s, MHD_OPTION_CONNECTION_LIMIT, connection_limit, MHD_OPTION_PER_IP_CONNECTION_LIMIT, address_limit,
      MHD_OPTION_NOTIFY_CONNECTION, &Impl::notify, impl.get(), MHD_OPTION_URI_LOG_CALLBACK, &screen_uri, nullptr,
      MHD_OPTION_NOTIFY_COMPLETED, &request_completed, nullptr, MHD_OPTION_END);
  if (impl->daemon == nullptr) return Unexpected{cannot};
  const MHD_DaemonInfo* info = MHD_get_daemon_info(impl->daemon, MHD_DAEMON_INFO_BIND_PORT);
  port_ = info != nullptr ? info->port : where->port;
  impl_ = std::move(impl);
  return port_;
}

void StatusServer::stop() {
  if (!impl_) return;
  MHD_stop_daemon(impl_->daemon);  // closes every connection and joins the threads
  impl_.reset();
  port_ = 0;
}

}  // namespace poet
