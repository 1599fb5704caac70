// Loading C plugins (plugins.hpp, docs/plugins.md).
#include "harness/user_methods/plugins.hpp"

#include "dampsym/plugin.h"
#include "harness/bounded_read.hpp"
#include "harness/case/case.hpp"
#include "harness/case/util.hpp"
#include "harness/user_methods/method_files.hpp"
#include "methods/plugin_buffers.hpp"
#include "methods/plugin_call.hpp"

#include <dlfcn.h>
#include <signal.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <map>
#include <set>

namespace dampsym {
namespace {

struct Loaded {
    std::map<std::string, std::vector<const MethodInfo*>> by_path; // canonical path -> rows
    std::deque<std::string> libraries; // the --plugin paths the rows point to (stable storage)
};

Loaded& loaded() {
    static Loaded l;
    return l;
}

[[noreturn]] void fault(const std::string& lib, const std::string& what) {
    throw InputError(quote_for_message(lib) + ": " + what);
}

// ---- containment (docs/plugins.md "Containment") ----------------------------------------------
// A plugin runs in dampsym's process. If it calls exit() or quick_exit() (any status) inside a
// call the host marked (plugin_call.hpp), the handler below names it and ends the process with
// status 3 before any other exit handler runs a flush that could pass for success: no report is
// written by this run. A crash signal inside a plugin is named and then takes its default action
// (death by the signal; the previous handler, e.g. the sanitizer's, runs first). _exit() and the
// exit_group system call bypass every handler and cannot be contained in-process; a plugin's
// endless loop is not contained either.
constexpr int kPluginEndedProcessStatus = 3;

void write_stderr(const char* s) {
    std::size_t n = std::strlen(s);
    while (n > 0) {
        const ssize_t w = ::write(2, s, n);
        if (w <= 0) return;
        s += w;
        n -= static_cast<std::size_t>(w);
    }
}

// "plugin method 'M' (LIB) in its step" from a site, into buf (no allocation: signal handlers).
void describe_site(const PluginCallSite& site, char* buf, std::size_t size) {
    std::snprintf(buf, size, "plugin %s%s%s (%s) in its %s", site.method ? "method '" : "",
                  site.method ? site.method : "entry", site.method ? "'" : "",
                  site.library ? site.library : "?", site.what);
}

void exit_inside_plugin() {
    const PluginCallSite* site = plugin_call_in_progress();
    if (!site) return; // dampsym's own exit
    char buf[1024];
    describe_site(*site, buf, sizeof buf);
    write_stderr("dampsym: ");
    write_stderr(buf);
    write_stderr(" ended the process (exit or quick_exit); the run did not complete and no report "
                 "was written (exit status 3)\n");
    ::_exit(kPluginEndedProcessStatus);
}

constexpr int kCrashSignals[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGSYS};
struct sigaction g_previous[sizeof kCrashSignals / sizeof kCrashSignals[0]];

void crash_inside_plugin(int sig, siginfo_t* info, void* uctx) {
    std::size_t k = 0;
    while (kCrashSignals[k] != sig) ++k;
    if (const PluginCallSite* site = plugin_call_in_progress()) {
        char buf[1024];
        describe_site(*site, buf, sizeof buf);
        write_stderr("dampsym: ");
        write_stderr(buf);
        write_stderr(" crashed (");
        write_stderr(strsignal(sig));
        write_stderr("); the run did not complete and no report was written\n");
    }
    // the previous disposition (default, or the sanitizer's handler) takes it from here
    sigaction(sig, &g_previous[k], nullptr);
    const struct sigaction& prev = g_previous[k];
    if ((prev.sa_flags & SA_SIGINFO) && prev.sa_sigaction)
        prev.sa_sigaction(sig, info, uctx);
    else if (prev.sa_handler != SIG_DFL && prev.sa_handler != SIG_IGN && prev.sa_handler)
        prev.sa_handler(sig);
    else
        raise(sig); // delivered when the handler returns (the signal is blocked until then)
}

void install_containment() {
    static const bool installed = [] {
        std::atexit(exit_inside_plugin);
        std::at_quick_exit(exit_inside_plugin);
        for (std::size_t k = 0; k < sizeof kCrashSignals / sizeof kCrashSignals[0]; ++k) {
            struct sigaction sa {};
            sa.sa_sigaction = crash_inside_plugin;
            sa.sa_flags = SA_SIGINFO | SA_ONSTACK;
            sigemptyset(&sa.sa_mask);
            sigaction(kCrashSignals[k], &sa, &g_previous[k]);
        }
        return true;
    }();
    (void)installed;
}

// ---- the probe step at load --------------------------------------------------------------------
// Each method takes one step of a 2-dimensional state (z = (0.5, 0.25), t = 0, h = 0.01) against
// host callbacks of simple closed forms; a callback outside the method's form that this step
// calls is a load error (a form declares which callbacks exist: plain rhs; conformal rhs and
// conformal_N; separable rhs, grad_T and force). The result of the step is not judged here.
struct Probe {
    int form = 0;
    const char* misuse = nullptr;
};
Probe& probe_of(void* ctx) {
    return *static_cast<Probe*>(ctx);
}
int probe_dim(void*) {
    return 2;
}
double probe_gamma(void*, double) {
    return 0.1;
}
double probe_damping(void*, double, double tau) {
    return std::exp(-0.2 * tau);
}
void probe_rhs(void*, double, const double* z, double* out) {
    out[0] = z[1];
    out[1] = -z[0] - 0.2 * z[1];
}
void probe_N(void* ctx, double, const double* z, double* out) {
    if (probe_of(ctx).form != DAMPSYM_FORM_CONFORMAL) {
        probe_of(ctx).misuse = "conformal_N";
        return;
    }
    out[0] = z[1];
    out[1] = -z[0];
}
void probe_grad_T(void* ctx, const double* p, double* out) {
    if (probe_of(ctx).form != DAMPSYM_FORM_SEPARABLE) {
        probe_of(ctx).misuse = "grad_T";
        return;
    }
    out[0] = p[0];
}
void probe_force(void* ctx, double, const double* q, double* out) {
    if (probe_of(ctx).form != DAMPSYM_FORM_SEPARABLE) {
        probe_of(ctx).misuse = "force";
        return;
    }
    out[0] = -q[0];
}

void probe_method(const std::string& lib, const char* lib_stable, const dampsym_method& m) {
    Probe probe{m.form, nullptr};
    dampsym_host host{&probe,     &probe_dim, &probe_gamma,  &probe_damping,
                      &probe_rhs, &probe_N,   &probe_grad_T, &probe_force};
    GuardedBuffer z(2), next(2), jac(4);
    const double z0[2] = {0.5, 0.25};
    z.arm_copy(z0);
    next.arm_unwritten();
    const PluginCallSite site{lib_stable, m.id, "probe step"};
    {
        const PluginCall mark(site);
        (void)m.step(m.method_ctx, &host, 0.0, 0.01, z.data(), next.data());
        if (m.step_jacobian && !probe.misuse) {
            z.arm_copy(z0);
            next.arm_unwritten();
            jac.arm_unwritten();
            (void)m.step_jacobian(m.method_ctx, &host, 0.0, 0.01, z.data(), next.data(),
                                  jac.data());
        }
    }
    if (probe.misuse) {
        static const char* const forms[] = {"", "plain", "conformal", "separable"};
        fault(lib, "method '" + std::string(m.id) + "' (" + forms[m.form] +
                       " form) calls the host callback " + probe.misuse + ", which the " +
                       forms[m.form] +
                       " form does not provide (seen in a probe step at load; docs/plugins.md)");
    }
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

// Validates every method of the descriptor, takes each one probe step, then registers them all
// (nothing is registered when one fails). `lib_stable` outlives the rows (their citation).
std::vector<const MethodInfo*> register_descriptor(const std::string& path, const char* lib_stable,
                                                   const dampsym_plugin_descriptor& d) {
    const std::vector<MethodInfo> rows = rows_of(path, d);
    for (int i = 0; i < d.n_methods; ++i) probe_method(path, lib_stable, d.methods[i]);
    std::vector<const MethodInfo*> out;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const dampsym_method& m = d.methods[i];
        MethodInfo row = rows[i];
        const std::string citation =
            std::string("plugin ") + lib_stable +
            (m.description ? std::string(": ") + quote_for_message(m.description, 400) : "");
        row.citation = citation; // copied into stable storage by register_runtime_method
        row.data = PluginStep{&m, lib_stable};
        out.push_back(register_runtime_method(row, lib_stable));
    }
    return out;
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
    install_containment(); // before any plugin code runs (its constructors, at dlopen)
    reg.libraries.push_back(quote_for_message(path));
    const char* lib_stable = reg.libraries.back().c_str();
    const PluginCallSite load_site{lib_stable, nullptr, "load (constructors)"};
    void* handle = nullptr;
    {
        const PluginCall mark(load_site);
        handle = dlopen(open_path.c_str(), RTLD_NOW | RTLD_LOCAL);
    }
    if (!handle) {
        const char* err = dlerror();
        fault(path, std::string("cannot load the plugin: ") +
                        quote_for_message(err ? err : "dlopen failed", 400));
    }
    void* sym = dlsym(handle, DAMPSYM_PLUGIN_ENTRY_NAME);
    if (!sym) {
        dlclose(handle);
        fault(path, std::string("no entry symbol '") + DAMPSYM_PLUGIN_ENTRY_NAME +
                        "' (a dampsym plugin exports it, include/dampsym/plugin.h)");
    }
    const auto entry = reinterpret_cast<dampsym_plugin_entry_fn>(sym);
    dampsym_plugin_descriptor d{};
    int rc = 0;
    {
        const PluginCallSite entry_site{lib_stable, nullptr, "entry"};
        const PluginCall mark(entry_site);
        rc = entry(DAMPSYM_PLUGIN_ABI_VERSION, &d);
    }
    if (rc != 0) {
        dlclose(handle);
        fault(path, "the entry returned " + std::to_string(rc) +
                        " (it does not speak ABI version " +
                        std::to_string(DAMPSYM_PLUGIN_ABI_VERSION) + "?)");
    }
    std::vector<const MethodInfo*> out;
    try {
        out = register_descriptor(path, lib_stable, d);
    } catch (...) {
        dlclose(handle);
        throw;
    }
    reg.by_path[key] = out; // the library stays loaded: its rows point into it
    return out;
}

std::vector<const MethodInfo*> register_plugin_methods(const std::string& source,
                                                       const dampsym_plugin_descriptor& d) {
    auto& reg = loaded();
    reg.libraries.push_back(quote_for_message(source));
    return register_descriptor(source, reg.libraries.back().c_str(), d);
}

bool is_plugin_method(const MethodInfo& m) {
    return std::holds_alternative<PluginStep>(m.data);
}

} // namespace dampsym
