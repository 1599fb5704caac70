// libFuzzer target: the method-file reader (src/harness/user_methods/method_files.cpp) and the
// coefficient expressions it evaluates (src/methods/coefficient_expr.cpp). The input is the text
// of a method file; it goes through check_method_text, which validates it exactly as
// load_method_file validates a file's contents but registers nothing (so the global method
// registry does not grow with the inputs, and no input is rejected only because an earlier one
// registered its id). Rejection must be an InputError (exit 2 naming the file and the key); any
// other exception, a crash or a sanitizer report is a finding. The coefficient expression parser
// is also fed the raw input. Run by ci/fuzz.sh; tests/fuzz/corpus/method is replayed in CI.
#include "fuzz_support.hpp"

#include "harness/user_methods/method_files.hpp"
#include "methods/coefficient_expr.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    dampsym::fuzz::expect_input_error(
        [&] { (void)dampsym::check_method_text(text, "fuzz-method.json"); });
    // The expression parser alone: a value or CoefficientExprError, nothing else.
    try {
        (void)dampsym::evaluate_coefficient_expr(text);
    } catch (const dampsym::CoefficientExprError&) {
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fuzz finding: coefficient expression threw: %s\n", e.what());
        std::abort();
    }
    return 0;
}
