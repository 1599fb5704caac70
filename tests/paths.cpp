// The build's paths (test_paths.hpp), from the definitions tests/CMakeLists.txt gives this file.
#include "test_paths.hpp"

namespace dampsym_test {

const char* test_data_dir() {
    return DAMPSYM_TEST_DATA;
}
const char* binary_path() {
    return DAMPSYM_BINARY;
}

} // namespace dampsym_test
