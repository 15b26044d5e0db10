#include "runtime/policy_saver.h"

#include <algorithm>
#include <optional>

namespace dynapath::runtime {
namespace {

// Whether the run continuing from `resume` saves `approach` again: it is
// still to run, or in progress before its --save-at step. Until then its
// section in the file may be anything (a kill between the file's write and
// the next checkpoint leaves a newer one); it is replaced.
bool SavesAgain(Approach approach, const std::vector<Approach>& approaches,
                const PolicyPlan& policy, int total_steps, const RunCheckpoint& resume) {
  for (size_t i = static_cast<size_t>(resume.pass); i < approaches.size(); ++i) {
    if (approaches[i] != approach) continue;
    if (i == static_cast<size_t>(resume.pass) && resume.policy) {
      const int save_step = policy.save_at == kSaveAtEnd ? total_steps : policy.save_at;
      return save_step >= resume.policy->step;  // its own step is saved on taking it over
    }
    return true;
  }
  return false;
}

}  // namespace

Result<PolicySaver> PolicySaver::Open(const PolicyPlan& policy,
                                      const std::vector<Approach>& approaches, int total_steps,
                                      const RunCheckpoint* resume) {
  PolicySaver saver;
  saver.path_ = policy.save_path;
  const std::string& path = saver.path_;
  Result<std::vector<PolicySection>> found = ReadPolicySections(path);
  const bool missing = !found && found.error().IsNotFound();
  if (found) {
    saver.sections_ = std::move(*found);
  } else if (!missing) {
    return Error::Option("save-policy", path +
                                            " is there and is not a policy file whose other "
                                            "sections could be kept (" +
                                            found.error().message +
                                            "): remove it or choose another path");
  }
  if (resume == nullptr) return saver;

  auto again = [&](Approach approach) {
    return SavesAgain(approach, approaches, policy, total_steps, *resume);
  };
  auto recorded = [&](Approach approach) {
    return std::any_of(resume->policy_file.begin(), resume->policy_file.end(),
                       [&](const SavedSection& entry) { return entry.approach == approach; });
  };
  const std::string fix = "; restore it, or run again without --resume";
  for (Approach approach : approaches) {
    if (IsLearningApproach(approach) && !again(approach) && !recorded(approach)) {
      return Error::Option("save-policy", "the checkpointed run saved no " +
                                              ApproachName(approach) +
                                              " section (it ran without --save-policy?): run "
                                              "again without --resume to save one");
    }
  }
  for (const SavedSection& entry : resume->policy_file) {
    if (again(entry.approach)) continue;
    const auto section = saver.Find(entry.approach);
    if (section != saver.sections_.end() && section->Fingerprint() == entry.fingerprint) continue;
    const std::string name = ApproachName(entry.approach);
    if (missing) {
      return Error::Option("save-policy", path + " is gone: at the checkpoint it held the run's " +
                                              name + " section" + fix);
    }
    return Error::Option(
        "save-policy",
        path +
            (section == saver.sections_.end() ? " no longer holds the " + name + " section it held"
                                              : "'s " + name + " section is not the one it held") +
            " at the checkpoint (the file was replaced or changed)" + fix);
  }
  for (const PolicySection& section : saver.sections_) {
    if (again(section.approach) || recorded(section.approach)) continue;
    return Error::Option("save-policy", path + " holds a " + ApproachName(section.approach) +
                                            " section the run neither saved nor found there when "
                                            "it started (another run's file?)" +
                                            fix);
  }
  return saver;
}

std::vector<PolicySection>::iterator PolicySaver::Find(Approach approach) {
  return std::find_if(sections_.begin(), sections_.end(),
                      [&](const PolicySection& held) { return held.approach == approach; });
}

Status PolicySaver::Save(const PolicyState& state) {
  Result<PolicySection> section = EncodePolicySection(state);
  if (!section) return section.error();
  const auto same = Find(state.approach);
  // What the file holds stays what sections_ says when the write fails.
  std::optional<PolicySection> replaced;
  if (same != sections_.end()) {
    replaced = std::move(*same);
    *same = std::move(*section);
  } else {
    sections_.push_back(std::move(*section));
  }
  Status written = WritePolicySections(path_, sections_);
  if (written) return Ok{};
  const auto back = Find(state.approach);
  if (replaced) {
    *back = std::move(*replaced);
  } else {
    sections_.erase(back);
  }
  return written.error().Prefixed("policy file " + path_ + ": ");
}

std::vector<SavedSection> PolicySaver::Record() const {
  std::vector<SavedSection> record;
  for (const PolicySection& section : sections_) {
    record.push_back(SavedSection{section.approach, section.Fingerprint()});
  }
  return record;
}

}  // namespace dynapath::runtime
