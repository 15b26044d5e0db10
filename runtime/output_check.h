#pragma once
// Output paths checked before any work starts: a folder where a file is
// wanted, a file where a folder is wanted, a missing parent folder or an
// unwritable place is one error naming the option, the path and the
// system's reason, instead of a failure after the work was done.

#include <string>
#include <vector>

#include "dynapath/result.h"

namespace dynapath::runtime {

// An output directory (--out): created with its parents when missing; it
// must then be a directory a file can be made in.
Status PrepareOutputDirectory(const std::string& dir, const std::string& option);
// Files a command will (re)write in `dir`: none of them may be a directory.
Status CheckOutputFiles(const std::string& dir, const std::vector<std::string>& names,
                        const std::string& option);
// An output file (--log, --save-policy): not a directory, in an existing
// folder a file can be made in (one is made and removed: /proc takes none,
// even from root), and writable itself if it exists.
Status CheckOutputFile(const std::string& path, const std::string& option);

}  // namespace dynapath::runtime
