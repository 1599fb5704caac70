#include "cli/cli.hpp"

#include <iostream>

int main(int argc, char** argv) {
    return dampsym::run_cli(argc, argv, std::cout, std::cerr);
}
