#include "tools/web/host_check.h"

#include <arpa/inet.h>
#include <netinet/in.h>

namespace dynapath::web {
namespace {

// A host and port as a Host header (or an Origin's authority) gives them.
struct HostPort {
  std::string host;  // a lower-case name or IPv4 address, or "[IPv6]" in canonical form
  int port = -1;     // -1: none given
};

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

bool ParsePort(std::string_view digits, int& port) {
  if (digits.empty() || digits.size() > 5) return false;
  int value = 0;
  for (char c : digits) {
    if (c < '0' || c > '9') return false;
    value = value * 10 + (c - '0');
  }
  if (value < 1 || value > 65535) return false;
  port = value;
  return true;
}

// "[" + the address in inet_ntop's canonical form + "]".
bool CanonicalIpv6(std::string_view text, std::string& out) {
  if (text.empty() || text.size() > 45) return false;
  const std::string copy(text);
  in6_addr address{};
  if (inet_pton(AF_INET6, copy.c_str(), &address) != 1) return false;
  char buffer[INET6_ADDRSTRLEN];
  if (inet_ntop(AF_INET6, &address, buffer, sizeof(buffer)) == nullptr) return false;
  out = "[" + std::string(buffer) + "]";
  return true;
}

// A DNS name or an IPv4 address, lower-cased: letters, digits, '.', '-', '_'.
bool CanonicalName(std::string_view text, std::string& out) {
  if (text.empty() || text.size() > 253) return false;
  out.clear();
  for (char c : text) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '_')) {
      return false;
    }
    out.push_back(c);
  }
  return true;
}

// host[:port] with host a name, an IPv4 address or a bracketed IPv6 one.
bool ParseHostPort(std::string_view text, HostPort& out) {
  if (text.empty() || text.size() > 300) return false;
  std::string_view rest;
  if (text.front() == '[') {
    const size_t close = text.find(']');
    if (close == std::string_view::npos || !CanonicalIpv6(text.substr(1, close - 1), out.host)) {
      return false;
    }
    rest = text.substr(close + 1);
  } else {
    const size_t colon = text.find(':');
    if (!CanonicalName(text.substr(0, colon), out.host)) return false;
    rest = colon == std::string_view::npos ? std::string_view() : text.substr(colon);
  }
  out.port = -1;
  if (rest.empty()) return true;
  return rest.front() == ':' && ParsePort(rest.substr(1), out.port);
}

// An --allow-host value: ParseHostPort's forms, or a bare IPv6 address.
bool ParseAllowed(std::string_view text, HostPort& out) {
  text = Trim(text);
  if (text.find(':') != text.rfind(':') && text.find('[') == std::string_view::npos) {
    out.port = -1;
    return CanonicalIpv6(text, out.host);
  }
  return ParseHostPort(text, out);
}

bool Allowed(const HostPort& given, int default_port, const HostPolicy& policy) {
  const int port = given.port >= 0 ? given.port : default_port;
  std::string bound;
  if (policy.bind.find(':') != std::string::npos) {
    if (!CanonicalIpv6(policy.bind, bound) || bound == "[::]") bound.clear();
  } else if (!CanonicalName(policy.bind, bound) || bound == "0.0.0.0") {
    bound.clear();
  }
  if (port == policy.port) {
    for (const char* own : {"localhost", "127.0.0.1", "[::1]"}) {
      if (given.host == own) return true;
    }
    if (!bound.empty() && given.host == bound) return true;
  }
  for (const std::string& value : policy.allowed) {
    HostPort allowed;
    if (ParseAllowed(value, allowed) && allowed.host == given.host &&
        (allowed.port < 0 || allowed.port == port)) {
      return true;
    }
  }
  return false;
}

}  // namespace

bool HostAllowed(std::string_view host, const HostPolicy& policy) {
  HostPort given;
  return ParseHostPort(Trim(host), given) && Allowed(given, 80, policy);
}

bool OriginAllowed(std::string_view origin, const HostPolicy& policy) {
  origin = Trim(origin);
  auto starts = [&](std::string_view scheme) {
    if (origin.size() < scheme.size()) return false;
    for (size_t i = 0; i < scheme.size(); ++i) {
      char c = origin[i];
      if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
      if (c != scheme[i]) return false;
    }
    return true;
  };
  int default_port = 0;
  std::string_view authority;
  if (starts("http://")) {
    default_port = 80;
    authority = origin.substr(7);
  } else if (starts("https://")) {
    default_port = 443;
    authority = origin.substr(8);
  } else {
    return false;
  }
  HostPort given;
  return ParseHostPort(authority, given) && Allowed(given, default_port, policy);
}

std::string AllowHostError(std::string_view value) {
  HostPort parsed;
  if (ParseAllowed(value, parsed)) return "";
  return "option --allow-host needs a host name or address, optionally with :PORT "
         "(runs.example.org, 192.168.1.5:8080, [fe80::1]:8080), got '" +
         std::string(value.substr(0, 100)) + "'";
}

}  // namespace dynapath::web
