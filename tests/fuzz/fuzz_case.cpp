// libFuzzer target: the case parser and validator (src/harness/case/case.cpp). The input is the
// text of a case file; it goes through parse_json_checked and parse_case as `dampsym run FILE`
// does. Rejection must be an InputError (exit 2 with file and key); any other exception, a crash or
// a sanitizer report is a finding. Run by ci/fuzz.sh; the corpus in tests/fuzz/corpus/case is
// replayed in CI by fuzz_replay (tests/fuzz/replay_main.cpp).
#include "fuzz_support.hpp"

#include "harness/case/case.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    dampsym::fuzz::expect_input_error([&] {
        const nlohmann::json j = dampsym::parse_json_checked(text, "fuzz.json");
        const dampsym::CaseSpec c = dampsym::parse_case(j, "fuzz.json", {});
        // What the runner computes from a valid case before any work.
        (void)dampsym::case_total_steps(c);
        (void)dampsym::case_predicted_seconds(c);
    });
    return 0;
}
