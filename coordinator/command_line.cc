#include "coordinator/command_line.h"

namespace dynapath::coordinator {

void DeclareCoordinatorCommandLine(runtime::OptionGroup& group, CoordinatorCommandLine& o) {
  runtime::DeclareProcessOptions(group, o.process, true);
  runtime::DeclareRunOptions(group, o.run);
  group.Option("--agents", o.agents, "N", "wait for N live agents before starting");
  runtime::DeclareWaitOptions(group, o.wait);
  group.Option("--give-up", o.give_up, "SECONDS",
               "fail when a training batch makes no progress this long although its agents "
               "are alive (its work is reassigned every 5 s before that)");
  runtime::DeclareLogOptions(group, o.log);
  group.Option("--out-lock-fd", o.out_lock_fd, "FD",
               "set by dynapath run: the inherited descriptor of its lock on --out (without "
               "it, the coordinator locks --out itself; -1)");
}

}  // namespace dynapath::coordinator
