// Where the tests find their data (tests/data) and the dampsym executable. Both are absolute paths
// of this build; they are compiled into one small file (paths.cpp) only, so that no other test
// file's object depends on where the checkout is (a compiler cache then serves every checkout).
#pragma once

namespace dampsym_test {

const char* test_data_dir(); // tests/data of the source tree
const char* binary_path();   // the dampsym executable of this build

} // namespace dampsym_test
