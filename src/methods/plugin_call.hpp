// Which plugin code the current thread is running (docs/plugins.md "Containment"). The host marks
// every call into a plugin — its entry at load, its step and step Jacobian, the probe step at load
// — with a PluginCall on the thread's stack, so that the process-exit and crash handlers installed
// by load_plugin (harness/user_methods/plugins.cpp) can tell an exit() or a fault inside a plugin
// from one of dampsym's own, and name the plugin: a plugin that ends the process can then never end
// it with status 0 and no report. Marking costs two thread-local stores per call.
#pragma once

namespace dampsym {

struct PluginCallSite {
    const char* library; // the --plugin path as given (may be null)
    const char* method;  // the method id (null for the entry)
    const char* what;    // "entry", "step", "step_jacobian", "probe step"
};

namespace detail {
// constant-initialised: readable from a signal handler without a TLS constructor
inline thread_local const PluginCallSite* current_plugin_call = nullptr;
} // namespace detail

// The plugin call the current thread is inside (null: dampsym's own code).
inline const PluginCallSite* plugin_call_in_progress() {
    return detail::current_plugin_call;
}

// Marks the thread as inside plugin code for the lifetime of the object (nests).
class PluginCall {
public:
    explicit PluginCall(const PluginCallSite& site) : prev_(detail::current_plugin_call) {
        detail::current_plugin_call = &site;
    }
    ~PluginCall() { detail::current_plugin_call = prev_; }
    PluginCall(const PluginCall&) = delete;
    PluginCall& operator=(const PluginCall&) = delete;

private:
    const PluginCallSite* prev_;
};

} // namespace dampsym
