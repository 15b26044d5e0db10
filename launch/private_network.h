#pragma once
// A private network for a run: a new user + network namespace with only a
// loopback interface. Multicast works inside it (so LCM's default udpm URL
// does), nothing leaves the machine, and two runs in two namespaces cannot
// hear each other. No root, no `ip` binary and no system set-up are needed
// where the kernel allows unprivileged user namespaces.

#include "dynapath/result.h"

namespace dynapath::launch {

// Moves the calling process into a new user + network namespace with only a
// loopback interface, brought up with multicast on and a route for
// 224.0.0.0/4, so LCM's default udpm URL works inside and nothing leaves
// the machine. Children started afterwards inherit it. Must be called while
// the process has a single thread (unshare(CLONE_NEWUSER) requires it).
//
// Inside, the caller's user and group appear as root (uid/gid 0 map to the
// caller's effective ids), so files it creates are still owned by the caller
// outside. When user namespaces are refused and the caller is root, only a
// network namespace is created.
//
// On error the process is left as it was (the whole set-up is first tried in
// a forked child), so callers can fall back to another transport.
Status EnterPrivateNetwork();

}  // namespace dynapath::launch
