#pragma once
/// Where the files eigenmass ships (tools/plot.py, data/) are: installed
/// beside the binary (cmake --install: PREFIX/share/eigenmass/), else in the
/// source tree it was built from. An installed tree needs no source tree.
#include <string>

namespace em {

/// The installed copy of `rel` (a path under the project's top, e.g.
/// "tools/plot.py") when the running binary has one at
/// <its folder>/../share/eigenmass/<rel>, else <source_dir>/<rel>.
std::string shippedFile(const std::string& rel, const std::string& source_dir);

}  // namespace em
