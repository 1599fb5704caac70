#include "cli/cli.hpp"

#include <csignal>
#include <iostream>

int main(int argc, char** argv) {
    // A write past the file-size limit (ulimit -f) fails with EFBIG, reported as an I/O error
    // (exit 3 naming the file), instead of SIGXFSZ killing the process with no message.
    std::signal(SIGXFSZ, SIG_IGN);
    return dampsym::run_cli(argc, argv, std::cout, std::cerr);
}
