// Loading C plugins (plugins.hpp, docs/plugins.md).
#include "harness/plugins.hpp"

#include "dampsym/plugin.h"
#include "harness/bounded_read.hpp"
#include "harness/case.hpp"
#include "harness/case_util.hpp"
#include "harness/method_files.hpp"

#include <dlfcn.h>

#include <deque>
#include <filesystem>
#include <map>
#include <set>

namespace dampsym {
namespace {

struct Loaded {
    std::map<std::string, std::vector<const MethodInfo*>> by_path; // canonical path -> rows
};

Loaded& loaded() {
    static Loaded l;
    return l;
}

[[noreturn]] void fault(const std::string& lib, const std::string& what) {
    throw InputError(lib + ": " + what);
}

Form form_of(const std::string& lib, const std::string& id, int code) {
    switch (code) {
    case DAMPSYM_FORM_PLAIN:
        return Form::plain;
    case DAMPSYM_FORM_CONFORMAL:
        return Form::conformal;
    case DAMPSYM_FORM_SEPARABLE:
        return Form::separable;
    default:
        fault(lib, "method '" + id + "': unknown form " + std::to_string(code) +
                       " (1 plain, 2 conformal, 3 separable)");
    }
}

unsigned claims_of(const std::string& lib, const std::string& id, unsigned bits) {
    constexpr unsigned known = DAMPSYM_CLAIM_CONFORMAL_SYMPLECTIC | DAMPSYM_CLAIM_SYMPLECTIC |
                               DAMPSYM_CLAIM_NEGATIVE_CONTROL;
    if (bits & ~known)
        fault(lib, "method '" + id + "': unknown claim bits " + std::to_string(bits & ~known));
    unsigned c = claim_none;
    if (bits & DAMPSYM_CLAIM_CONFORMAL_SYMPLECTIC) c |= claim_conformal_symplectic;
    if (bits & DAMPSYM_CLAIM_SYMPLECTIC) c |= claim_symplectic_if_undamped;
    return c; // a negative control claims nothing: its checks are expected to fail
}

// Validates every method of the descriptor before any is registered.
std::vector<MethodInfo> rows_of(const std::string& lib, const dampsym_plugin_descriptor& d) {
    if (d.abi_version != DAMPSYM_PLUGIN_ABI_VERSION)
        fault(lib, "plugin ABI version " + std::to_string(d.abi_version) + ", dampsym speaks " +
                       std::to_string(DAMPSYM_PLUGIN_ABI_VERSION));
    if (d.n_methods < 1 || d.n_methods > 1000 || !d.methods)
        fault(lib, "the descriptor lists " + std::to_string(d.n_methods) +
                       " methods (1 to 1000, with a non-null methods array)");
    std::vector<MethodInfo> rows;
    std::set<std::string> ids;
    for (int i = 0; i < d.n_methods; ++i) {
        const dampsym_method& m = d.methods[i];
        const std::string where = "methods[" + std::to_string(i) + "]";
        if (!m.id) fault(lib, where + ": null id");
        const std::string id(m.id);
        if (!valid_case_id(id))
            fault(lib, where + ": '" + quote_for_message(id) +
                           "' is not a valid method id (1 to 100 characters of A-Z a-z 0-9 . _ "
                           "-, starting with a letter or digit)");
        if (!m.step) fault(lib, "method '" + id + "': null step function");
        if (m.order < 1 || m.order > 20)
            fault(lib, "method '" + id + "': order " + std::to_string(m.order) + " (1 to 20)");
        if (!ids.insert(id).second) fault(lib, "method '" + id + "' is listed twice");
        for (const auto& b : method_catalog())
            if (b.id == id)
                fault(lib, "method '" + id + "' is a built-in method; a plugin cannot shadow it");
        if (const std::string other = loaded_method_source(id); !other.empty())
            fault(lib, "method '" + id + "' is also defined in " + other);
        // the citation is set by load_plugin (its storage is kept by register_runtime_method)
        rows.push_back(MethodInfo{m.id, m.order, false, form_of(lib, id, m.form),
                                  claims_of(lib, id, m.claims), "", PluginStep{&m}});
    }
    return rows;
}

} // namespace

std::vector<const MethodInfo*> load_plugin(const std::string& path) {
    std::error_code ec;
    const std::filesystem::path canonical = std::filesystem::weakly_canonical(path, ec);
    const std::string key = ec ? path : canonical.string();
    auto& reg = loaded();
    if (const auto it = reg.by_path.find(key); it != reg.by_path.end()) return it->second;
    // a path without '/' would be searched on the library path: name the file itself
    const std::string open_path = path.find('/') == std::string::npos ? "./" + path : path;
    // dlopen of a FIFO blocks until a writer comes: regular files only
    if (const auto why = not_regular_reason(open_path, false); !why.empty())
        fault(path, "cannot load the plugin: " + why);
    void* handle = dlopen(open_path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
        const char* err = dlerror();
        fault(path, std::string("cannot load the plugin: ") + (err ? err : "dlopen failed"));
    }
    void* sym = dlsym(handle, DAMPSYM_PLUGIN_ENTRY_NAME);
    if (!sym) {
        dlclose(handle);
        fault(path, std::string("no entry symbol '") + DAMPSYM_PLUGIN_ENTRY_NAME +
                        "' (a dampsym plugin exports it, include/dampsym/plugin.h)");
    }
    const auto entry = reinterpret_cast<dampsym_plugin_entry_fn>(sym);
    dampsym_plugin_descriptor d{};
    if (const int rc = entry(DAMPSYM_PLUGIN_ABI_VERSION, &d); rc != 0) {
        dlclose(handle);
        fault(path, "the entry returned " + std::to_string(rc) +
                        " (it does not speak ABI version " +
                        std::to_string(DAMPSYM_PLUGIN_ABI_VERSION) + "?)");
    }
    std::vector<MethodInfo> rows;
    try {
        rows = rows_of(path, d);
    } catch (...) {
        dlclose(handle);
        throw;
    }
    std::vector<const MethodInfo*> out;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const dampsym_method& m = d.methods[i];
        MethodInfo row = rows[i];
        const std::string citation = std::string("plugin ") + path +
                                     (m.description ? std::string(": ") + m.description : "");
        row.citation = citation; // copied into stable storage by register_runtime_method
        out.push_back(register_runtime_method(row, path));
    }
    reg.by_path[key] = out; // the library stays loaded: its rows point into it
    return out;
}

bool is_plugin_method(const MethodInfo& m) {
    return std::holds_alternative<PluginStep>(m.data);
}

} // namespace dampsym
