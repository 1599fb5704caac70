// C plugins (docs/plugins.md, include/dampsym/plugin.h): shared libraries whose
// hand-written steps become method rows (PluginStep, stepped by methods/plugin_kernel.hpp), found
// by find_method after the built-in catalog like a method file's rows, so every diagnostic, the
// matrix and the reports treat them as built-in methods.
//
// Sources: `dampsym run|methods|matrix --plugin LIB` (repeatable). A library is loaded once per
// process (by canonical path) and stays loaded until the process ends.
//
// Every fault of loading — dlopen failure, no entry symbol, an entry that returns nonzero, an ABI
// version other than 1, a malformed descriptor (no methods or more than 1000, a null id or step,
// an id that is not a valid method id, a duplicate id, an id of a built-in method or of a loaded
// method, an unknown form, an order outside 1..20, an unknown claim bit) — is an InputError
// "LIB: what" (exit 2); nothing of a bad library is registered.
#pragma once

#include "core/method.hpp"

#include <string>
#include <vector>

struct dampsym_plugin_descriptor; // include/dampsym/plugin.h

namespace dampsym {

// Loads the plugin library and registers its methods; returns them (also when loaded before).
std::vector<const MethodInfo*> load_plugin(const std::string& path);
// Registers the methods of a descriptor that did not come from a library (the Python module's
// callables, python/): the same checks and probe step as load_plugin, `source` naming them in
// messages and citations. The descriptor and its methods must outlive the process's runs.
std::vector<const MethodInfo*> register_plugin_methods(const std::string& source,
                                                       const dampsym_plugin_descriptor& d);
// Whether the method row is a plugin's.
bool is_plugin_method(const MethodInfo& m);

} // namespace dampsym
