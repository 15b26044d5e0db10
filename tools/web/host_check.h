#pragma once
// Who may talk to `dynapath web`: the checks that keep other web sites out.
//
// The server is read-only and bound to 127.0.0.1, yet a page the user opens
// elsewhere can reach it: through DNS rebinding (a hostile name that
// resolves to 127.0.0.1, whose requests carry that name in their Host
// header) and through a WebSocket (browsers let any site open one to any
// address; its handshake carries the site's Origin). So every request's
// Host header, and the Origin of a WebSocket handshake that has one, must
// name this server:
//
//   * the address it is bound to (unless 0.0.0.0 or ::), `localhost`,
//     `127.0.0.1` or `[::1]`, with the server's port (no port: 80);
//   * or a name given with --allow-host NAME (any port) or NAME:PORT.
//
// Pure functions, no I/O: the server, its tests and the fuzzer share them.

#include <string>
#include <string_view>
#include <vector>

namespace dynapath::web {

struct HostPolicy {
  std::string bind;                  // the bound address: "127.0.0.1", "::1", "0.0.0.0", ...
  int port = 0;                      // the bound port
  std::vector<std::string> allowed;  // --allow-host values: NAME or NAME:PORT
};

// A Host header's value: "127.0.0.1:8080", "[::1]:8080", "localhost:8080",
// "runs.example.org". Names compare without case; IPv6 literals by value.
bool HostAllowed(std::string_view host, const HostPolicy& policy);

// An Origin header's value: "http://127.0.0.1:8080". Only http and https
// origins (default ports 80 and 443) whose host and port pass HostAllowed;
// "null", file:, extensions' and other schemes are refused.
bool OriginAllowed(std::string_view origin, const HostPolicy& policy);

// Checks an --allow-host value (NAME, NAME:PORT, an IPv4 address, an IPv6
// address with or without brackets, [IPv6]:PORT): "" when usable, else why not.
std::string AllowHostError(std::string_view value);

}  // namespace dynapath::web
