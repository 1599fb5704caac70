// libFuzzer target: the --set KEY=VALUE override parser (parse_override) and its application to
// a valid case (parse_case with overrides), as `dampsym run CASE --set ...` does. Each input line
// is one --set argument. Rejection must be an InputError; anything else is a finding.
#include "fuzz_support.hpp"

#include "harness/case/case.hpp"

namespace {

// A small valid case (verify/cases style) the overrides are applied to.
const char* kCase = R"({
  "id": "fuzz-set", "title": "t", "source": "F Figs 4.2", "suites": ["fuzz"],
  "problem": { "id": "oscillator", "omega": 1.0, "gamma": 0.1 },
  "methods": ["cimp", "csv1"],
  "t_end": 1.0, "dt_ladder": [0.1, 0.05], "output_dt": 0.5,
  "diagnostics": ["energy", "invariants", "error"],
  "expect": {
    "e": { "metric": "error.final_abs", "methods": ["csv1"], "le": 1.0 },
    "r": { "metric": "error.final_abs", "ratio": ["csv1", "cimp"], "le": 10.0 }
  }
})";

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    std::vector<std::string> sets;
    std::string::size_type start = 0;
    while (start <= text.size() && sets.size() < 8) {
        const auto nl = text.find('\n', start);
        sets.push_back(
            text.substr(start, nl == std::string::npos ? std::string::npos : nl - start));
        if (nl == std::string::npos) break;
        start = nl + 1;
    }
    static const nlohmann::json base = nlohmann::json::parse(kCase);
    dampsym::fuzz::expect_input_error([&] {
        for (const auto& s : sets) (void)dampsym::parse_override(s);
    });
    dampsym::fuzz::expect_input_error([&] { (void)dampsym::parse_case(base, "fuzz.json", sets); });
    return 0;
}
