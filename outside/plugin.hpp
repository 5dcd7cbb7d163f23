#pragma once
/// A method from outside as a compiled plugin (outside/eigenmass_plugin.h,
/// docs/plugins.md): a shared library's u' run under every in-house
/// integrator, a registry row like the built-in ones. Its runs go through a
/// child process (outside/isolate.hpp): a crash or a hang ends that run as a
/// failure, never the harness.
#include <memory>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "solver/method.hpp"
#include "solver/trajectory.hpp"

namespace em {

/// "NAME=path" as given to `option` (--plugin, --run): its two halves;
/// std::invalid_argument, one line naming the option, when either is missing.
std::pair<std::string, std::string> splitNamedFile(const std::string& option, const std::string& value);

/// Load `path` as method `name`: dlopen, the four symbols, the ABI version.
/// Adds the method's row (isolated) and returns its id; the same name and
/// path again return the same id. Throws std::invalid_argument, one line
/// naming the file (or the name), for a name taken or not a scene name, a
/// file that is not a loadable library, a missing symbol, another ABI.
Method addPlugin(const std::string& name, const std::string& path);

/// Create the plugin for `m` and ask its u' at the initial state, in a child
/// process: a crash, a hang, an error code, a NULL from create or a
/// non-finite u' is refused in one line naming the file (before any run).
void probePlugin(Method method, const Model& m);

/// Whether `method` is a plugin's (its row was added by addPlugin).
bool isPlugin(Method method);

/// Seconds a plugin's call may go without returning before it counts as hung
/// (default kPluginTimeout; --plugin-timeout).
void setPluginTimeout(double seconds);
double pluginTimeout();

/// Where a plugin method came from, for its report: the library's path and
/// SHA-256, the ABI; null for any other method.
nlohmann::json pluginSource(Method method);

/// A run of a plugin's method, in a child process: the trajectory as
/// simulate makes it, or, when the plugin crashed or hung, the samples up to
/// the last output time before that (the run repeated that far) and a
/// `plugin` failure at the time of its last call.
Trajectory simulateIsolated(const Model& m, const CheckedRunSpec& spec, const SampleObserver& observe);

/// The plugin's u' at states (internal order), evaluated in a child process
/// (crosscheck); on a mechanism the constrained u', the loops closed around
/// the plugin's tree u' with its own A^-1 G^T (eigenmass_plugin.h). Throws std::runtime_error naming the file when it fails.  // q: (nq), u, udot: (nu) each
std::vector<Eigen::VectorXd> pluginUdots(Method method, const Model& m, const std::vector<Eigen::VectorXd>& q,
                                         const std::vector<Eigen::VectorXd>& u);

}  // namespace em
