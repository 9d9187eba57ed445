#pragma once
// The status socket's endpoints as a pure function: a request's method, path and query in, the response out.
// No sockets here (status_server.h carries it over HTTP), so every route, error and header is tested directly.
// The routes, their parameters' bounds and the 404's list are status_route_table.h's.
//
//   GET /                                                       the dashboard (text/html, every asset inside it)
//   GET /status /pairs /pairs/{id} /pairs/{id}/episode /archive /workers /events?since=N[&limit=M] /healthz
//                                                               application/json
//   GET /metrics                                                Prometheus text format 0.0.4
//   GET /pictures/{picture}.{format}, /pictures/pairs/{id}/{picture}.{format}   the run's and a pair's pictures
//
// HEAD is GET without the body. Another method on one of these paths is 405 with Allow: GET, HEAD; any other
// path is 404; a bad query value is 400. Every error has a JSON body: {"status": 404, "error": "..."}.

#include <map>
#include <string>

#include "coordinator/status/status_board.h"
#include "coordinator/status/status_route_table.h"

namespace poet {

struct StatusResponse {
  int status = 200;
  std::string content_type = kJsonType;
  std::string body;
  std::string allow;  // the Allow header, set on 405
};

// The query's parameters, decoded, in order (a key may repeat).
using QueryParams = std::multimap<std::string, std::string>;

// The response to one request. Never throws on any input (a board read error is a 500 with a JSON body).
StatusResponse status_response(const StatusBoard& board, const std::string& method, const std::string& path,
                               const QueryParams& query);

// An error response: the status and a JSON body {"status": ..., "error": message}.
StatusResponse error_response(int status, const std::string& message);

}  // namespace poet
