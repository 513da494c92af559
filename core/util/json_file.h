#pragma once
// Reading a JSON file the user gave, with one wording for every failure.
#include <string>

#include <nlohmann/json.hpp>

namespace seamap {

// The parsed contents of the JSON file at `path`. `what` names the file for
// the user, with the option that gave it if any ("config file", "rig's
// motion file (--motion)"). Throws
// InputError(path, 0, "", "cannot read the <what>: <reason>"), the reason
// being "no such file", "not a regular file" (a FIFO would block), "cannot
// open it" or "not JSON: <the parser's message>".
nlohmann::json ReadJsonFile(const std::string& path, const std::string& what);

}  // namespace seamap
