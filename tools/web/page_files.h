#pragma once
// The page's files (tools/web/page/), embedded into the binary at build
// time (embed_page.cmake): nothing is read or fetched at run time.

#include <map>
#include <string>

#include "tools/web/web_server.h"

namespace dynapath::web {

// "/index.html", "/app.js", "/style.css" with their content types.
std::map<std::string, PageFile> PageFiles();

}  // namespace dynapath::web
