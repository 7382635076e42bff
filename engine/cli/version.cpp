// keel --version: the project version and the commit the binary was built from (keel_version.hpp, generated
// on every build by engine/cli/version.cmake).
#include "keel_version.hpp"

namespace keel::cli {

const char* version_string();  // declared in commands.hpp (not included here: it pulls in CLI11)

const char* version_string() { return "keel " KEEL_VERSION " (commit " KEEL_GIT_COMMIT ")"; }

}  // namespace keel::cli
