// Methods added at run time (method files, src/harness/user_methods/method_files.hpp): find_method
// (src/methods/catalog.cpp) looks here after the built-in catalog. Rows live in stable storage
// until the process ends; loading happens before any case runs (single-threaded), lookups after.
#pragma once

#include "core/method.hpp"

#include <string_view>
#include <vector>

namespace dampsym {

// The loaded row with this id, or nullptr.
const MethodInfo* find_loaded_method(std::string_view id);
// Every loaded row, in load order.
std::vector<const MethodInfo*> loaded_methods();

} // namespace dampsym
