// dampsym_bench: Google Benchmark executable (see bench/bench_common.hpp for the counters and
// bench/bench_report.py for the report and acceptance ratios). Besides Google Benchmark's own
// flags (--benchmark_filter, --benchmark_out=FILE --benchmark_out_format=json, ...) it accepts
//   --quick   one repetition and a short minimum time per benchmark (a smoke test only).
// Times are CPU times of the benchmark thread's process (Google Benchmark's default); every
// benchmark is single-threaded (run_cases is called with jobs = 1).
#include "bench/bench_common.hpp"

#include <cstring>
#include <string>
#include <vector>

namespace dampsym::bench {

Options& options() {
    static Options o;
    return o;
}

} // namespace dampsym::bench

int main(int argc, char** argv) {
    using namespace dampsym::bench;
    std::vector<char*> args;
    for (int i = 0; i < argc; ++i) {
        if (i > 0 && std::strcmp(argv[i], "--quick") == 0)
            options().quick = true;
        else
            args.push_back(argv[i]);
    }
    int n = static_cast<int>(args.size());
    benchmark::Initialize(&n, args.data());
    if (benchmark::ReportUnrecognizedArguments(n, args.data())) return 2;

    benchmark::AddCustomContext("dampsym.h", std::to_string(kStep));
    benchmark::AddCustomContext("dampsym.gamma", std::to_string(kGamma));
    benchmark::AddCustomContext("dampsym.steps_1dof", std::to_string(kSteps1Dof));
    benchmark::AddCustomContext("dampsym.steps_nbody", std::to_string(kStepsNBody));
    benchmark::AddCustomContext("dampsym.build", DAMPSYM_BENCH_BUILD);
    benchmark::AddCustomContext("dampsym.time", "cpu");
    benchmark::AddCustomContext("dampsym.quick", options().quick ? "true" : "false");

    register_harness_benchmarks();
    register_peer_benchmarks();
    register_reference_benchmark();
    register_overhead_benchmarks();
    register_pde_benchmarks();
    register_workprecision_benchmarks();
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
