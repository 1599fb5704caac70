// Hostile input, tested by class (issue "Bad input that still gets through"): every numeric key of
// a case with a number that overflows a double, every object with a duplicate key, nesting at
// several depths anywhere and through --set, every parameter of every problem at and beyond the
// edges of its valid range, every method that does not apply to a problem, files that are not
// regular or too large, duplicate case ids, limits on the work a case asks for, the wording of
// the messages, and what `dampsym list` documents. Each rejection must be an InputError (exit
// status 2) naming the file and the key; none may crash, hang or read unbounded data.
#include "cli_support.hpp"
#include "harness/case/case.hpp"
#include "harness/registry.hpp"
#include "reference/oscillator_exact.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <limits>
#include <quadmath.h>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace {

using dampsym::CaseSpec;
using dampsym::InputError;
using dampsym::load_case;
using dampsym_test::CliResult;
using dampsym_test::run;
using dampsym_test::TempDir;
using dampsym_test::write_text;
using json = nlohmann::json;
namespace fs = std::filesystem;
namespace limits = dampsym::limits;

// A valid case that uses every kind of key: every top-level key, problem parameters, a ladder,
// output grid, a sweep, reference settings and checks with every optional key.
json rich_case() {
    return json::parse(R"({
      "id": "rich", "title": "t", "source": "s", "notes": "n", "suites": ["x", "y"],
      "problem": { "id": "oscillator", "omega": 1.0, "gamma": 0.1, "q0": 1.0, "p0": 0.0 },
      "methods": ["cimp", "csv1", "rk4"],
      "t0": 0.0, "t_end": 1.0, "dt_ladder": [0.1, 0.05, 0.025], "output_dt": 0.5,
      "diagnostics": ["error", "order", "invariants", "stability-sweep"],
      "stability_sweep": { "omega": 1.0, "gamma": [0.0, 0.5, 0.25], "h": [0.1, 0.2, 0.1] },
      "reference": { "stepper": "rk8pd", "epsrel": 1e-12, "epsabs": 1e-13 },
      "expect": {
        "a": { "metric": "order.slope", "methods": ["cimp"], "near": 2.0, "tol": 0.1 },
        "b": { "metric": "error.final_abs", "methods": "all", "le": 1.0, "dt": 0.1, "abs": true,
               "negative_control": false, "note": "n" } } })");
}

// Loads `text` from a file in a fresh directory; returns the error message ("" if accepted).
std::string load_error(const std::string& text, const std::vector<std::string>& sets = {},
                       const std::string& name = "case.json") {
    TempDir dir;
    const fs::path file = dir / name;
    // These tests are about the parser, not about checks: a case object without checks gets the
    // stated reason (inserted as text, so duplicate keys and deep values stay as written).
    std::string body = text;
    if (!body.empty() && body[0] == '{' && body.find("\"expect\"") == std::string::npos &&
        body.find("no_checks_because") == std::string::npos)
        body.insert(1, "\"no_checks_because\": \"parser unit test\", ");
    write_text(file, body);
    try {
        (void)load_case(file.string(), sets);
    } catch (const InputError& e) {
        const std::string msg = e.what();
        // Every rejection names the file it is about (or the --set that gave the value).
        CHECK((msg.find(file.string()) != std::string::npos ||
               msg.find("--set") != std::string::npos));
        return msg.empty() ? "(empty message)" : msg;
    }
    return "";
}

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

// Every path (as dampsym names keys: a.b[2].c) to a leaf of `j` satisfying `pred`.
void leaves(const json& j, const std::string& path, const std::function<bool(const json&)>& pred,
            std::vector<std::pair<std::string, json::json_pointer>>& out,
            const json::json_pointer& ptr = json::json_pointer()) {
    if (j.is_object()) {
        for (auto it = j.begin(); it != j.end(); ++it)
            leaves(it.value(), path.empty() ? it.key() : path + "." + it.key(), pred, out,
                   ptr / it.key());
    } else if (j.is_array()) {
        for (std::size_t i = 0; i < j.size(); ++i)
            leaves(j[i], path + "[" + std::to_string(i) + "]", pred, out, ptr / i);
    } else if (pred(j)) {
        out.push_back({path, ptr});
    }
}

// The case text with the leaf at `ptr` replaced by the literal `literal`.
std::string with_literal(json j, const json::json_pointer& ptr, const std::string& literal) {
    const std::string marker = "@@MARK@@";
    j[ptr] = marker;
    std::string text = j.dump(2);
    const auto pos = text.find("\"" + marker + "\"");
    REQUIRE(pos != std::string::npos);
    text.replace(pos, marker.size() + 2, literal);
    return text;
}

std::string deep(std::size_t depth) {
    return std::string(depth, '[') + std::string(depth, ']');
}

} // namespace

TEST_CASE("bad input: the rich case is valid (the base of every test below)", "[bad-input]") {
    CHECK(load_error(rich_case().dump(2)) == "");
}

TEST_CASE("bad input: every numeric key with a number that overflows a double", "[bad-input]") {
    const json c = rich_case();
    std::vector<std::pair<std::string, json::json_pointer>> numbers;
    leaves(
        c, "", [](const json& v) { return v.is_number(); }, numbers);
    REQUIRE(numbers.size() >= 20);
    for (const auto& [path, ptr] : numbers) {
        for (const std::string& literal : {std::string("1e400"), std::string("-1e400"),
                                           std::string("1e999999"), std::string(400, '9')}) {
            INFO(path << " = " << literal.substr(0, 20));
            const std::string err = load_error(with_literal(c, ptr, literal));
            CHECK(contains(err, path + ": number"));
            CHECK(contains(err, "overflows a double"));
            CHECK(err.size() < 400); // the 400-digit literal is not echoed whole
        }
        // Through --set: a scalar key directly, an array element inside the whole array.
        const auto bracket = path.find('[');
        const std::string set =
            bracket == std::string::npos
                ? path + "=1e400"
                : path.substr(0, bracket) + "=" +
                      with_literal(c[ptr.parent_pointer()], json::json_pointer("/" + ptr.back()),
                                   "1e400");
        INFO("--set " << set);
        const std::string err = load_error(rich_case().dump(2), {set});
        CHECK(contains(err, "--set"));
        CHECK((contains(err, "overflows a double") || contains(err, "must be finite")));
    }
}

TEST_CASE("bad input: NaN, inf and 1e400 from --set are told apart and name file and key",
          "[bad-input]") {
    const std::string text = rich_case().dump(2);
    const std::string nan_err = load_error(text, {"problem.gamma=NaN"});
    CHECK(contains(nan_err, "problem.gamma"));
    CHECK(contains(nan_err, "NaN"));
    CHECK_FALSE(contains(nan_err, "null"));
    const std::string big_err = load_error(text, {"problem.gamma=1e400"});
    CHECK(contains(big_err, "problem.gamma"));
    CHECK(contains(big_err, "overflows a double"));
    CHECK_FALSE(contains(big_err, "null"));
    CHECK(nan_err != big_err);
    // --set values are named as such, not blamed on the file's content
    CHECK(contains(big_err, "set by --set problem.gamma=1e400"));
}

TEST_CASE("bad input: every object with a duplicate key", "[bad-input]") {
    const json c = rich_case();
    std::vector<std::string> objects;
    std::function<void(const json&, const std::string&)> walk = [&](const json& j,
                                                                    const std::string& path) {
        if (j.is_object()) {
            objects.push_back(path);
            for (auto it = j.begin(); it != j.end(); ++it)
                walk(it.value(), path.empty() ? it.key() : path + "." + it.key());
        }
    };
    walk(c, "");
    REQUIRE(objects.size() == 7); // top level, problem, sweep, reference, expect, expect.a, .b
    for (const auto& path : objects) {
        json j = c;
        json::json_pointer ptr;
        std::string rest = path;
        while (!rest.empty()) {
            const auto dot = rest.find('.');
            ptr /= rest.substr(0, dot);
            rest = dot == std::string::npos ? "" : rest.substr(dot + 1);
        }
        json& obj = j[ptr];
        const std::string first = obj.begin().key();
        obj["@@DUP@@"] = obj.begin().value();
        std::string text = j.dump(2);
        text.replace(text.find("\"@@DUP@@\""), 9, "\"" + first + "\"");
        INFO("duplicate of " << first << " in " << (path.empty() ? "(top level)" : path));
        const std::string err = load_error(text);
        CHECK(contains(err, (path.empty() ? "" : path + ".") + first + ": duplicate key"));
    }
    // and through --set, as a value that is an object with a duplicate key
    const std::string set_err = load_error(c.dump(), {"problem={\"id\": 1, \"id\": 2}"});
    CHECK(contains(set_err, "--set problem: id: duplicate key"));
    // The issue's instances.
    CHECK(contains(load_error(R"({"id": "x", "problem": {"id": "oscillator"}, "methods": ["csv1"],
                                "t_end": 1, "dt": 0.1, "dt": 0.05})"),
                   "dt: duplicate key"));
    CHECK(contains(load_error(R"({"id": "x", "problem": {"id": "oscillator"}, "methods": ["csv1"],
                                "methods": ["cimp"], "t_end": 1, "dt": 0.1})"),
                   "methods: duplicate key"));
}

TEST_CASE("bad input: nesting at several depths anywhere, in files and through --set",
          "[bad-input]") {
    const json c = rich_case();
    // Places a nested value can go: declared strings, an unknown key, a number, an array, a
    // check's note, and a key inside the problem.
    const std::vector<std::string> places{"/title",       "/notes",    "/zzz",
                                          "/problem/q0",  "/methods",  "/expect/a/note",
                                          "/problem/zzz", "/dt_ladder"};
    const std::vector<std::size_t> depths{1, 5, 10, 13, 14, 15, 16, 17, 100, 1000, 50000};
    for (const auto& place : places) {
        const json::json_pointer ptr(place);
        // levels above the value: the top-level object and the objects on the way
        const auto base = static_cast<std::size_t>(std::count(place.begin(), place.end(), '/'));
        for (std::size_t d : depths) {
            INFO(place << " nested " << d << " deep");
            const std::string err = load_error(with_literal(c, ptr, deep(d)));
            CHECK_FALSE(err.empty()); // never valid: none of these keys takes nested arrays
            // total depth: the enclosing objects, then d arrays
            const bool too_deep = base + d > static_cast<std::size_t>(limits::max_depth);
            CHECK(contains(err, "nesting deeper than") == too_deep);
        }
    }
    // Through --set: a deep value, and a key with too many components.
    for (std::size_t d : {2ul, 16ul, 17ul, 1000ul, 50000ul}) {
        INFO("--set title=" << d << " deep");
        const std::string err = load_error(c.dump(), {"title=" + deep(d)});
        CHECK_FALSE(err.empty());
        CHECK(contains(err, "nesting deeper than") == (d > 16));
    }
    std::string key = "a";
    for (int i = 0; i < 50000; ++i) key += ".a";
    CHECK(contains(load_error(c.dump(), {key + "=1"}), "key components"));
    // A deep top-level value is not an object.
    CHECK_FALSE(load_error(deep(100000)).empty());
    // In-process through the whole command line too (the value is copied after parsing).
    TempDir cases, out;
    write_text(cases / "deep.json", with_literal(c, json::json_pointer("/title"), deep(50000)));
    const CliResult r = run({"--cases", cases.str(), "run", (cases / "deep.json").string(), "--set",
                             "notes=" + deep(50000), "--out", (out / "o").string()});
    CHECK(r.status == 2);
}

TEST_CASE("bad input: every parameter of every problem at and beyond its range edges",
          "[bad-input]") {
    for (const auto& prob : dampsym::problem_catalog()) {
        std::string method;
        for (const auto& m : dampsym::method_catalog())
            if (method.empty() && dampsym::method_applies(m.id, prob.id)) method = m.id;
        REQUIRE_FALSE(method.empty());
        json base = {{"id", "edge"},        {"problem", {{"id", prob.id}}},
                     {"methods", {method}}, {"t_end", 1.0},
                     {"dt", 0.5},           {"diagnostics", {"cost"}}};
        REQUIRE(load_error(base.dump()) == "");
        for (const auto& ps : prob.params) {
            const std::string key = "problem." + ps.name;
            INFO(prob.id << " " << key);
            CHECK_FALSE(ps.doc.empty());
            auto with = [&](const json& v) {
                json j = base;
                j["problem"][ps.name] = v;
                return j.dump();
            };
            if (!ps.choices.empty()) {
                for (const auto& name : ps.choices) CHECK(load_error(with(name)) == "");
                CHECK(contains(load_error(with("bogus")), key + ": must be one of"));
                CHECK(contains(load_error(with(0)), key + ": must be one of"));
                continue;
            }
            // Every bound is finite: no parameter is unbounded.
            CHECK(std::isfinite(ps.range.lo));
            CHECK(std::isfinite(ps.range.hi));
            const double inf = std::numeric_limits<double>::infinity();
            std::vector<double> beyond{std::nextafter(ps.range.lo, -inf),
                                       std::nextafter(ps.range.hi, inf), -1e300, 1e300};
            std::vector<double> at;
            (ps.range.lo_open ? beyond : at).push_back(ps.range.lo);
            (ps.range.hi_open ? beyond : at).push_back(ps.range.hi);
            auto value = [&](double x) {
                if (!ps.is_array) return json(x);
                json a = ps.default_array;
                a[0] = x; // one entry at the edge, the others valid
                return a;
            };
            const std::string ekey = ps.is_array ? key + "[0]" : key;
            for (double x : at) {
                INFO("at the edge: " << x);
                const std::string err = load_error(with(value(x)));
                // nbody's dim = 2 is valid but does not match the default 3-D arrays
                if (prob.id == "nbody" && ps.name == "dim" && x == 2.0)
                    CHECK(contains(err, "dim*N"));
                else
                    CHECK(err == "");
            }
            for (double x : beyond) {
                INFO("beyond the edge: " << x);
                CHECK(contains(load_error(with(value(x))), ekey + ": must be in"));
                // through --set too (scalars)
                if (!ps.is_array) {
                    std::ostringstream set;
                    set.precision(17);
                    set << key << "=" << x;
                    const std::string err = load_error(base.dump(), {set.str()});
                    CHECK(contains(err, key + " (set by --set " + key + "="));
                }
            }
            if (ps.integer) {
                // a fraction inside the range (a flag's range is [0, 1]), so that only the
                // whole-number rule can reject it
                CHECK(ps.range.lo + 1 <= ps.range.hi);
                CHECK(contains(load_error(with(ps.range.lo + 0.5)),
                               key + ": must be a whole number"));
            }
            if (ps.is_array) {
                json a = json::array();
                for (int i = 0; i < ps.max_size + 1; ++i) a.push_back(ps.default_array[0]);
                CHECK(contains(load_error(with(a)), key + ": has "));
            }
        }
    }
}

TEST_CASE("bad input: the oscillator's exact solution is right over its whole parameter range",
          "[bad-input]") {
    // Regression: for γ ≥ ~1.3e154, γ² overflowed and the "exact" solution returned q(1) = 0.5.
    // Now γ is limited to [0, 1e6]; at every corner of the parameter box the closed form agrees
    // with a quad-precision evaluation of the same formula.
    const json base = rich_case();
    CHECK(contains(load_error(base.dump(), {"problem.gamma=1.3e154"}), "problem.gamma"));
    CHECK(contains(load_error(base.dump(), {"problem.gamma=1e7"}), "must be in [0, 1e+06]"));
    using Q = __float128;
    for (double omega : {1e-6, 1e-3, 1.0, 1e3, 1e6})
        for (double gamma : {0.0, 1e-6, 1.0, 1e3, 1e6})
            for (double q0 : {-1e6, 1.0})
                for (double p0 : {1e6, 0.0}) {
                    // times where e^{-γt} is representable in quad precision and not all lost
                    const double t = 20.0 / std::max({1.0, gamma, omega});
                    const auto s = dampsym::oscillator_exact(omega, gamma, q0, p0, t);
                    const Q w = omega, g = gamma, tt = t, b2 = w * w - g * g;
                    Q c, sn;
                    if (b2 > 0) {
                        const Q b = sqrtq(b2);
                        c = cosq(b * tt);
                        sn = sinq(b * tt) / b;
                    } else if (b2 < 0) {
                        const Q k = sqrtq(-b2);
                        c = coshq(k * tt);
                        sn = sinhq(k * tt) / k;
                    } else {
                        c = 1;
                        sn = tt;
                    }
                    const Q e = expq(-g * tt);
                    const Q q = e * (Q(q0) * c + (Q(p0) + g * Q(q0)) * sn);
                    const Q p = e * (Q(p0) * c - (g * Q(p0) + w * w * Q(q0)) * sn);
                    // the size of the terms, to which the rounding error is proportional
                    const double tq = static_cast<double>(
                        fabsq(e * Q(q0) * c) + fabsq(e * Q(p0) * sn) + fabsq(e * g * Q(q0) * sn));
                    const double tp =
                        static_cast<double>(fabsq(e * Q(p0) * c) + fabsq(e * g * Q(p0) * sn) +
                                            fabsq(e * w * w * Q(q0) * sn));
                    INFO("omega " << omega << " gamma " << gamma << " q0 " << q0 << " p0 " << p0);
                    REQUIRE(std::isfinite(s.q));
                    REQUIRE(std::isfinite(s.p));
                    CHECK(std::abs(s.q - static_cast<double>(q)) <= 1e-13 * tq + 1e-300);
                    CHECK(std::abs(s.p - static_cast<double>(p)) <= 1e-13 * tp + 1e-300);
                }
}

TEST_CASE("bad input: every problem's forms are finite at every edge of its parameter box",
          "[bad-input]") {
    dampsym::for_each_type(dampsym::ProblemList{}, [&]<class P>() {
        const auto specs = P::param_specs();
        dampsym::ParamMap defaults;
        for (const auto& s : specs) {
            if (s.is_array)
                defaults.arrays[s.name] = s.default_array;
            else
                defaults.scalars[s.name] = s.default_value;
        }
        for (const auto& s : specs) {
            if (!s.choices.empty() || s.integer) continue;
            for (double x : {s.range.lo, s.range.hi}) {
                if ((x == s.range.lo && s.range.lo_open) || (x == s.range.hi && s.range.hi_open))
                    continue;
                dampsym::ParamMap m = defaults;
                if (s.is_array)
                    m.arrays[s.name][0] = x;
                else
                    m.scalars[s.name] = x;
                INFO(P::id << " " << s.name << " = " << x);
                const P p = P::from_params(m);
                const dampsym::Vec z0 = p.initial_state();
                dampsym::Vec f(z0.size());
                p.rhs(0.0, z0, f);
                CHECK(f.allFinite());
                std::vector<double> inv(P::invariant_names.size() + 1);
                p.invariants(0.0, z0, inv.data());
                for (std::size_t i = 0; i < P::invariant_names.size(); ++i)
                    CHECK(std::isfinite(inv[i]));
                if constexpr (P::has_energy) CHECK(std::isfinite(p.energy(z0)));
                CHECK(std::isfinite(p.Gamma(1.0)));
                // periodic damping: the conformal factor e^{±2Γ} stays representable
                if constexpr (!dampsym::detail::declares_constant_gamma<P>())
                    CHECK(std::isfinite(std::exp(2.0 * std::abs(p.Gamma(M_PI / 4.0)))));
            }
        }
    });
}

TEST_CASE("bad input: a method named that does not apply to the problem", "[bad-input]") {
    int rejected = 0;
    for (const auto& prob : dampsym::problem_catalog())
        for (const auto& m : dampsym::method_catalog()) {
            if (dampsym::method_applies(m.id, prob.id)) continue;
            const json c = {{"id", "na"},        {"problem", {{"id", prob.id}}},
                            {"methods", {m.id}}, {"t_end", 1.0},
                            {"dt", 0.5},         {"diagnostics", {"cost"}}};
            INFO(std::string(m.id) << " on " << prob.id);
            CHECK(contains(load_error(c.dump()), "methods[0]: method '" + std::string(m.id) +
                                                     "' (" +
                                                     std::string(dampsym::form_name(m.form)) +
                                                     " form) does not apply to problem"));
            ++rejected;
        }
    CHECK(rejected > 0); // csv1 on the rigid body among them
}

TEST_CASE("bad input: lists name each entry once", "[bad-input]") {
    const std::string text = rich_case().dump();
    const std::string diag = load_error(text, {R"(diagnostics=["error", "error"])"});
    CHECK(contains(diag, "diagnostics[1] (set by --set diagnostics="));
    CHECK(contains(diag, "diagnostic 'error' listed twice"));
    CHECK(contains(load_error(text, {R"(methods=["csv1", "csv1"])"}), "methods[1] (set by"));
    CHECK(contains(load_error(text, {R"(suites=["x", "x"])"}), "suite 'x' listed twice"));
    CHECK(contains(load_error(text, {R"(expect.a.methods=["cimp", "cimp"])"}),
                   "method 'cimp' listed twice"));
    CHECK(contains(load_error(text, {"dt_ladder=[0.1, 0.1, 0.05]"}), "listed twice"));
    // the same in a file: names the key alone
    json c = rich_case();
    c["diagnostics"] = {"error", "order", "error"};
    CHECK(contains(load_error(c.dump()), "diagnostics[2]: diagnostic 'error' listed twice"));
}

TEST_CASE("bad input: case ids are restricted and unique in a run", "[bad-input]") {
    const std::string text = rich_case().dump();
    for (const std::string& bad :
         {std::string("a\nb"), std::string("<b>x</b>"), std::string("# h"), std::string("-x"),
          std::string("a b"), std::string("a/b"), std::string(101, 'a'), std::string(1 << 20, 'a'),
          std::string("caf\xc3\xa9")}) {
        INFO("id " << json(bad).dump().substr(0, 40));
        const std::string err = load_error(text, {"id=" + json(bad).dump()});
        CHECK(contains(err, "id"));
        CHECK(err.size() < 500);
    }
    CHECK(load_error(text, {"id=" + std::string(100, 'a')}) == "");
    CHECK(load_error(text, {"id=osc-error-fig44-g0.001_v2"}) == "");

    TempDir cases, out;
    write_text(cases / "a.json", text);
    json b = rich_case();
    b["id"] = "other";
    write_text(cases / "b.json", b.dump());
    auto status = [&](std::vector<std::string> args, const std::string& must) {
        args.insert(args.begin(), {"--cases", cases.str(), "run"});
        args.insert(args.end(), {"--out", (out / "o").string()});
        const CliResult r = run(args);
        INFO(dampsym_test::describe(args, r));
        CHECK(contains(r.err, must));
        CHECK_FALSE(fs::exists(out / "o" / "report.json"));
        return r.status;
    };
    CHECK(status({"rich", "rich"}, "named twice") == 2);
    CHECK(status({(cases / "a.json").string(), "rich"}, "named twice") == 2);
    CHECK(status({"rich", "other", "--set", "id=same"}, "after --set id") == 2);
    write_text(out / "c.json", text); // another file with the same id
    CHECK(status({"rich", (out / "c.json").string()}, "is also the id of") == 2);
}

TEST_CASE("bad input: case files are regular files of bounded size, checked before reading",
          "[bad-input]") {
    TempDir dir;
    const fs::path fifo = dir / "fifo.json";
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    auto err_of = [](const fs::path& p) {
        try {
            (void)load_case(p.string(), {});
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    CHECK(contains(err_of(fifo), "a FIFO")); // returns at once: no writer is waited for
    fs::create_symlink("/dev/zero", dir / "zero.json");
    CHECK(contains(err_of(dir / "zero.json"), "a character device"));
    fs::create_directory(dir / "dir.json");
    CHECK(contains(err_of(dir / "dir.json"), "a directory"));
    {
        // sparse: 16 MiB + 1 byte of zeros, no disk space used
        const fs::path big = dir / "big.json";
        write_text(big, "");
        fs::resize_file(big, limits::max_file_bytes + 1);
        CHECK(contains(err_of(big), "larger than 16 MiB"));
        fs::resize_file(big, limits::max_file_bytes);
        CHECK(contains(err_of(big), "malformed JSON")); // at the limit it is read (and parsed)
    }
    CHECK(contains(err_of(dir / "missing.json"), "cannot open"));
    // The same through the command line, and in the cases directory.
    TempDir out;
    for (const auto& p : {fifo, dir / "zero.json", dir / "dir.json"}) {
        const CliResult r = run({"run", p.string(), "--out", (out / "o").string()});
        CHECK(r.status == 2);
        CHECK(contains(r.err, p.string()));
    }
    const CliResult scan = run({"--cases", dir.str(), "list"});
    CHECK(scan.status == 2);
}

TEST_CASE("bad input: targets that are directories or non-.json files are not looked up as ids",
          "[bad-input]") {
    TempDir dir, out;
    write_text(dir / "rich.json", rich_case().dump());
    fs::create_directory(dir / "adir");
    write_text(dir / "case.txt", rich_case().dump());
    const std::string cwd = fs::current_path().string();
    fs::current_path(dir.path());
    const CliResult a = run({"--cases", dir.str(), "run", "adir", "--out", (out / "o").string()});
    const CliResult b =
        run({"--cases", dir.str(), "run", "case.txt", "--out", (out / "o").string()});
    const CliResult c = run({"--cases", dir.str(), "run", "adir/", "--out", (out / "o").string()});
    fs::current_path(cwd);
    CHECK(a.status == 2);
    CHECK(contains(a.err, "is a directory"));
    CHECK(b.status == 2);
    CHECK(contains(b.err, "does not end in .json"));
    CHECK(c.status == 2);
    CHECK(contains(c.err, "a directory"));
}

TEST_CASE("bad input: limits on the work a case asks for", "[bad-input]") {
    const std::string text = rich_case().dump();
    json ladder = json::array(); // 1, 1/2, ..., 1/32: all divide t_end = 1 and output_dt = 1
    for (std::size_t i = 0; i < limits::max_ladder; ++i) ladder.push_back(1.0 / double(i + 1));
    CHECK(load_error(text, {"output_dt=1", "dt_ladder=" + ladder.dump()}) == "");
    ladder.push_back(1.0 / 33.0);
    CHECK(contains(load_error(text, {"output_dt=1", "dt_ladder=" + ladder.dump()}),
                   "has 33 step sizes (at most 32)"));
    json big = json::array();
    for (int i = 0; i < 100000; ++i) big.push_back(1.0 / (i + 1));
    CHECK(contains(load_error(text, {"dt_ladder=" + big.dump()}), "at most 32"));
    // steps per run: 1e9 accepted, 2e9 not
    CHECK(load_error(text, {"t_end=1e7", "dt_ladder=[1, 0.5, 0.1]", "output_dt=1e3"}) == "");
    CHECK(load_error(text, {"t_end=1e9", "dt_ladder=[1, 0.5, 0.1]", "output_dt=1e3",
                            "expect.b.dt=1"}) != "");
    CHECK(contains(load_error(text, {"t_end=1e9", "dt_ladder=[1, 0.5, 0.1]", "output_dt=1e3"}),
                   "dt_ladder[1] (set by --set dt_ladder=[1, 0.5, 0.1]): too many steps"));
    CHECK(contains(load_error(text, {"t_end=1e10"}),
                   "t_end (set by --set t_end=1e10): |t_end| must be <= 1e9"));
    CHECK(contains(load_error(text, {"t0=-2e9"}), "|t0| must be <= 1e9"));
    // output points: at most the step limit (1e9); the memory of a stored grid is checked at run
    // time (run --max-memory; a streamed grid needs none: tests/test_limits.cpp)
    CHECK(contains(load_error(text, {"output_dt=1e-4", "t_end=1e6"}),
                   "output_dt (set by --set output_dt=1e-4): too many steps"));
    CHECK(contains(load_error(text, {"stability_sweep.h=[1e-4, 1, 1e-4]",
                                     "stability_sweep.gamma=[0, 1000, 0.5]"}),
                   "at most 1e6"));
    CHECK(contains(load_error(text, {"reference.epsrel=1e-300"}), "reference.epsrel"));
    CHECK(contains(load_error(text, {"reference.epsabs=0.5"}), "reference.epsabs"));
    // the duration estimate that run prints for long cases
    TempDir dir;
    write_text(dir / "long.json", text);
    const CaseSpec c = load_case((dir / "long.json").string(), {"t_end=1e7", "output_dt=1e3"});
    CHECK(dampsym::case_total_steps(c) == 3.0 * (1e8 + 2e8 + 4e8));
    CHECK(dampsym::case_predicted_seconds(c) > 100.0);
}

TEST_CASE("bad input: poincare needs output_dt equal to the forcing period", "[bad-input]") {
    json c = {{"id", "p"},           {"problem", {{"id", "driven-pendulum"}}},
              {"methods", {"csv1"}}, {"t_end", 20.0 * M_PI},
              {"dt", M_PI / 50.0},   {"diagnostics", {"poincare"}}};
    CHECK(contains(load_error(c.dump()), "output_dt: the poincare diagnostic needs output_dt"));
    c["output_dt"] = M_PI;
    CHECK(contains(load_error(c.dump()), "got 3.14159"));
    c["output_dt"] = 2.0 * M_PI;
    CHECK(load_error(c.dump()) == "");
}

TEST_CASE("bad input: messages say what is wrong, briefly", "[bad-input]") {
    const std::string text = rich_case().dump();
    // an 80 KB value is not echoed whole
    const std::string err =
        load_error(text, {"title=" + json(std::vector<double>(8000, 1.5)).dump()});
    CHECK(contains(err, "title"));
    CHECK(err.size() < 400);
    // a problem without invariants
    json pend = {
        {"id", "p"},
        {"problem", {{"id", "pendulum"}}},
        {"methods", {"csv1"}},
        {"t_end", 1.0},
        {"dt", 0.5},
        {"diagnostics", {"invariants"}},
        {"expect",
         {{"x", {{"metric", "invariants.H.max_step_rel"}, {"methods", "all"}, {"le", 1}}}}}};
    const std::string inv = load_error(pend.dump());
    CHECK(contains(inv, "declares no conformal invariants"));
    CHECK_FALSE(contains(inv, "(known: )"));
    // masses of the wrong length are blamed on masses, not on q
    json nb = {{"id", "n"},
               {"problem", {{"id", "nbody"}, {"masses", {1.0, 1.0, 1.0, 1.0}}}},
               {"methods", {"csv1"}},
               {"t_end", 1.0},
               {"dt", 0.5}};
    const std::string mass = load_error(nb.dump());
    CHECK(contains(mass, "masses lists N = 4 bodies"));
    // enum-like parameters take names
    nb["problem"] = {{"id", "nbody"}, {"potential", "lennard-jones"}};
    CHECK(load_error(nb.dump()) == "");
    nb["problem"]["potential"] = 1;
    CHECK(contains(load_error(nb.dump()), "must be one of \"gravity\", \"lennard-jones\""));
    // an unknown subcommand is named
    const CliResult r = run({"frobnicate"});
    CHECK(r.status == 2);
    CHECK(contains(r.err, "frobnicate"));
}

TEST_CASE("bad input: list documents parameters, invariants and metrics", "[bad-input]") {
    TempDir cases;
    write_text(cases / "rich.json", rich_case().dump());
    const CliResult text = run({"--cases", cases.str(), "list"});
    REQUIRE(text.status == 0);
    for (const char* word :
         {"I1", "z3", "lj_sigma", "\"gravity\"  (one of gravity | lennard-jones)", "H_gamma",
          "casimir", "max_step_res", "reference_error_estimate", "docs/case-keys.md", "[0, 1e+06]"})
        CHECK(contains(text.out, word));
    const CliResult js = run({"--cases", cases.str(), "list", "--json"});
    REQUIRE(js.status == 0);
    const json j = json::parse(js.out);
    std::size_t params = 0;
    for (const auto& p : j["problems"]) {
        CHECK(p.contains("invariants"));
        for (const auto& ps : p["params"]) {
            ++params;
            CHECK_FALSE(ps["doc"].get<std::string>().empty());
            CHECK(ps.contains("default"));
            CHECK((ps.contains("range") || ps.contains("choices")));
        }
    }
    CHECK(params >= 30);
    for (const auto& d : dampsym::known_diagnostics()) {
        bool found = false;
        for (const auto& row : j["diagnostics"])
            if (row["id"] == d) found = !row["metrics"].empty();
        CHECK(found);
    }
}

TEST_CASE("bad input: docs/case-keys.md documents every case key", "[bad-input]") {
    const std::string doc = dampsym_test::read_text(fs::path(dampsym_test::test_data_dir()) / ".." /
                                                    ".." / "docs" / "case-keys.md");
    for (const char* key : {"id",        "title",     "source",      "notes",  "suites",
                            "problem",   "methods",   "t0",          "t_end",  "dt",
                            "dt_ladder", "output_dt", "diagnostics", "expect", "stability_sweep",
                            "reference", "metric",    "near",        "tol",    "le",
                            "ge",        "lt",        "gt",          "abs",    "negative_control",
                            "note",      "stepper",   "epsrel",      "epsabs", "omega",
                            "gamma",     "h"})
        CHECK(contains(doc, "`" + std::string(key) + "`"));
    // and every top-level key the parser accepts is among them: an unknown key's message lists
    // the allowed ones
    const std::string err = load_error(rich_case().dump(), {"zzz=1"});
    const auto open = err.find("(allowed: ");
    REQUIRE(open != std::string::npos);
    std::string list = err.substr(open + 10, err.find(')', open) - open - 10);
    std::size_t start = 0;
    while (start < list.size()) {
        const auto comma = list.find(", ", start);
        const std::string k = list.substr(start, comma - start);
        CHECK(contains(doc, "`" + k + "`"));
        start = comma == std::string::npos ? list.size() : comma + 2;
    }
}
