// The Python extension dampsym._dampsym (docs/python.md): the C++ API (include/dampsym/dampsym.hpp)
// with the GIL released while it runs, and Python callables as plugin methods. A callable step
// becomes a dampsym_method (include/dampsym/plugin.h) whose step and step Jacobian are the
// trampolines below, registered by register_plugin_methods like a C plugin's: the same checks,
// probe step, kernel (methods/plugin_kernel.hpp: guard cells, statuses, E_n by central differences
// without a Jacobian) and report notes. Each trampoline takes the GIL, since the runner calls it
// from its worker threads.
#include "dampsym/dampsym.hpp"
#include "dampsym/plugin.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace py = pybind11;

namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

// The host callbacks of one call into a Python step, as the `problem` argument; valid only during
// that call (the pointer is cleared after it, and a use later is an error).
struct Host {
    const dampsym_host* host = nullptr;
    int dim = 0;

    const dampsym_host& live() const {
        if (!host) throw std::runtime_error("the problem argument is only valid during its step");
        return *host;
    }
    Array apply(void (*fn)(void*, double, const double*, double*), double t, const Array& x, int n,
                const char* what) const {
        if (x.ndim() != 1 || x.shape(0) != n)
            throw py::value_error(std::string(what) + ": expected a vector of length " +
                                  std::to_string(n));
        Array out(n);
        fn(live().host_ctx, t, x.data(), out.mutable_data());
        return out;
    }
};

struct PyMethod {
    std::string id, description, source;
    py::object step, jacobian;
    dampsym_method method{};
    dampsym_plugin_descriptor descriptor{};
};

Array copy_of(const double* z, int d) {
    Array a(d);
    std::memcpy(a.mutable_data(), z, sizeof(double) * static_cast<std::size_t>(d));
    return a;
}

// Copies a callable's array result of `n` elements into out; a wrong shape is the step's error.
void copy_result(const py::handle& value, double* out, py::ssize_t rows, py::ssize_t cols,
                 const std::string& what) {
    const Array a = Array::ensure(value);
    if (!a) throw std::runtime_error(what + " did not return an array of numbers");
    const bool vector_ok = cols == 0 && a.ndim() == 1 && a.shape(0) == rows;
    const bool matrix_ok = cols > 0 && a.ndim() == 2 && a.shape(0) == rows && a.shape(1) == cols;
    if (!vector_ok && !matrix_ok)
        throw std::runtime_error(what + " returned an array of shape " +
                                 py::str(a.attr("shape")).cast<std::string>() + ", expected (" +
                                 std::to_string(rows) +
                                 (cols > 0 ? ", " + std::to_string(cols) : std::string(",")) + ")");
    std::memcpy(out, a.data(), sizeof(double) * static_cast<std::size_t>(a.size()));
}

// Set while register_step runs the plugin probe step on this thread (plugins.cpp): a C plugin's
// probe result is not judged, so a Python error there is a step that could not be taken (a
// callable written for the problems' dimensions may fail on the probe's 2-dimensional state).
thread_local bool t_probing = false;

// Calls the step (jac == nullptr) or the Jacobian callable; a Python exception becomes the run's
// error status with its message (the runner records a kernel's exception).
int call_python(PyMethod& m, const dampsym_host* host, double t, double h, const double* z,
                double* z_next, double* jac) {
    std::string failure;
    {
        py::gil_scoped_acquire gil;
        const int d = host->dim(host->host_ctx);
        auto view = std::make_shared<Host>(Host{host, d});
        try {
            py::object problem = py::cast(view);
            const py::object r = (jac ? m.jacobian : m.step)(t, copy_of(z, d), h, problem);
            if (!jac) {
                copy_result(r, z_next, d, 0, "step");
            } else {
                const py::tuple pair = r.cast<py::tuple>();
                if (pair.size() != 2) throw std::runtime_error("jacobian must return (z_next, J)");
                copy_result(pair[0], z_next, d, 0, "jacobian's z_next");
                copy_result(pair[1], jac, d, d, "jacobian's J");
            }
        } catch (py::error_already_set& e) {
            failure = e.what();
        } catch (const std::exception& e) {
            failure = e.what();
        }
        view->host = nullptr;
    }
    if (!failure.empty() && t_probing) return 1;
    if (!failure.empty())
        throw std::runtime_error("python method " + m.id + " (" + (jac ? "jacobian" : "step") +
                                 "): " + failure);
    return 0;
}

int step_trampoline(void* ctx, const dampsym_host* host, double t, double h, const double* z,
                    double* z_next) {
    return call_python(*static_cast<PyMethod*>(ctx), host, t, h, z, z_next, nullptr);
}

int jacobian_trampoline(void* ctx, const dampsym_host* host, double t, double h, const double* z,
                        double* z_next, double* jac) {
    return call_python(*static_cast<PyMethod*>(ctx), host, t, h, z, z_next, jac);
}

// Registers a callable step as a plugin method (checks, probe step). Once registered, the record
// lives as long as the process (its row points into it) and is never freed; a refused one is
// (register_plugin_methods registers nothing when it throws).
void register_step(const std::string& id, py::object step, py::object jacobian, int order, int form,
                   unsigned claims, const std::string& description, const std::string& source) {
    auto owned = std::make_unique<PyMethod>(
        PyMethod{id, description, source, std::move(step), std::move(jacobian), {}, {}});
    PyMethod* m = owned.get();
    m->method.id = m->id.c_str();
    m->method.description = m->description.empty() ? nullptr : m->description.c_str();
    m->method.order = order;
    m->method.form = form;
    m->method.claims = claims;
    m->method.step = &step_trampoline;
    m->method.step_jacobian = m->jacobian.is_none() ? nullptr : &jacobian_trampoline;
    m->method.method_ctx = m;
    m->descriptor =
        dampsym_plugin_descriptor{DAMPSYM_PLUGIN_ABI_VERSION, m->source.c_str(), 1, &m->method};
    struct Probing {
        Probing() { t_probing = true; }
        ~Probing() { t_probing = false; }
    } probing;
    dampsym::api::register_plugin_methods(m->descriptor, source);
    (void)owned.release(); // the registry's row points into it from now on
}

py::tuple run(const std::vector<std::string>& targets, const dampsym::api::Options& o) {
    dampsym::api::RunResult r;
    {
        py::gil_scoped_release release;
        r = dampsym::api::run(targets, o);
    }
    return py::make_tuple(r.report_json, r.series_json, r.exit_status);
}

py::tuple matrix(const std::vector<std::string>& globs, const dampsym::api::Options& o) {
    dampsym::api::Matrix m;
    {
        py::gil_scoped_release release;
        m = dampsym::api::matrix(globs, o);
    }
    return py::make_tuple(m.matrix_json, m.report_json, m.exit_status);
}

py::list check_method(const std::string& id) {
    py::list out;
    for (const auto& c : dampsym::api::check_method(id))
        out.append(py::dict(py::arg("name") = c.name, py::arg("what") = c.what,
                            py::arg("expected") = c.expected, py::arg("holds") = c.holds,
                            py::arg("agrees") = c.agrees, py::arg("value") = c.value,
                            py::arg("tolerance") = c.tolerance));
    return out;
}

py::tuple cli(const std::vector<std::string>& args) {
    std::string out, err;
    int status = 0;
    {
        py::gil_scoped_release release;
        status = dampsym::api::cli(args, out, err);
    }
    return py::make_tuple(status, out, err);
}

void bind_host(py::module_& m) {
    py::class_<Host, std::shared_ptr<Host>>(m, "Problem",
                                            "The problem's callbacks during one step (its form's)")
        .def_property_readonly("dim", [](const Host& h) { return h.dim; })
        .def("gamma", [](const Host& h, double t) { return h.live().gamma(h.live().host_ctx, t); })
        .def("damping_factor",
             [](const Host& h, double t, double tau) {
                 return h.live().damping_factor(h.live().host_ctx, t, tau);
             })
        .def("rhs", [](const Host& h, double t,
                       const Array& z) { return h.apply(h.live().rhs, t, z, h.dim, "rhs"); })
        .def("N", [](const Host& h, double t,
                     const Array& z) { return h.apply(h.live().conformal_N, t, z, h.dim, "N"); })
        .def("force",
             [](const Host& h, double t, const Array& q) {
                 return h.apply(h.live().force, t, q, h.dim / 2, "force");
             })
        .def("grad_T", [](const Host& h, const Array& p) {
            const int n = h.dim / 2;
            if (p.ndim() != 1 || p.shape(0) != n)
                throw py::value_error("grad_T: expected a vector of length " + std::to_string(n));
            Array out(n);
            h.live().grad_T(h.live().host_ctx, p.data(), out.mutable_data());
            return out;
        });
}

} // namespace

PYBIND11_MODULE(_dampsym, m) {
    m.doc() = "dampsym's C++ core (use the dampsym package, docs/python.md)";
    py::register_exception<dampsym::api::InputError>(m, "InputError", PyExc_ValueError);
    py::register_exception<dampsym::api::OutputError>(m, "OutputError", PyExc_OSError);
    py::class_<dampsym::api::Options>(m, "Options")
        .def(py::init<>())
        .def_readwrite("jobs", &dampsym::api::Options::jobs)
        .def_readwrite("time_budget", &dampsym::api::Options::time_budget)
        .def_readwrite("keep_series", &dampsym::api::Options::keep_series)
        .def_readwrite("method_files", &dampsym::api::Options::method_files)
        .def_readwrite("plugins", &dampsym::api::Options::plugins)
        .def_readwrite("cases_dir", &dampsym::api::Options::cases_dir);
    bind_host(m);
    m.def("version", &dampsym::api::version);
    m.def("run", &run);
    m.def("matrix", &matrix);
    m.def("load_method", &dampsym::api::load_method);
    m.def("load_method_file", &dampsym::api::load_method_file);
    m.def("load_plugin", &dampsym::api::load_plugin);
    m.def("check_method", &check_method);
    m.def("cli", &cli);
    m.def("register_step", &register_step);
    m.attr("FORM_PLAIN") = static_cast<int>(DAMPSYM_FORM_PLAIN);
    m.attr("FORM_CONFORMAL") = static_cast<int>(DAMPSYM_FORM_CONFORMAL);
    m.attr("FORM_SEPARABLE") = static_cast<int>(DAMPSYM_FORM_SEPARABLE);
    m.attr("CLAIM_CONFORMAL_SYMPLECTIC") =
        static_cast<unsigned>(DAMPSYM_CLAIM_CONFORMAL_SYMPLECTIC);
    m.attr("CLAIM_SYMPLECTIC") = static_cast<unsigned>(DAMPSYM_CLAIM_SYMPLECTIC);
    m.attr("CLAIM_NEGATIVE_CONTROL") = static_cast<unsigned>(DAMPSYM_CLAIM_NEGATIVE_CONTROL);
}
