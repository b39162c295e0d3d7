// tubecast_mpi_fault: the failure protocol of cli/mpi_session.h end to end, for
// run_fault_test.sh. A render's shape in miniature: a "load" phase in which rank FAIL_RANK may
// fail, a "composite" phase, then rank 0 writes OUT_FILE. Errors end the process the way tubecast's
// main() does (cli/main.cpp): RankFailure printed by rank 0 only; any other error printed, then
// MpiSession::abortIfLeftAlone.
//
//   tubecast_mpi_fault barrier FAIL_RANK CODE OUT_FILE   FAIL_RANK throws Error(CODE) inside the
//                                                         load phase (-1: nobody fails)
//   tubecast_mpi_fault abort FAIL_RANK CODE OUT_FILE     FAIL_RANK throws Error(CODE) outside any
//                                                         phase, while the others wait in a barrier
#include <fstream>
#include <iostream>
#include <string>

#include "cli/mpi_session.h"

namespace {

int run(const std::string& mode, int failRank, int code, const std::string& outFile) {
    tc::cli::MpiSession mpi;
    const bool fails = mpi.rank() == failRank;
    const std::string message = "data.tcb: cannot read brick " + std::to_string(mpi.rank());
    if (mode == "abort" && fails) throw tc::Error(tc::ExitCode(code), message);
    mpi.phase("load", [&] {
        if (fails) throw tc::Error(tc::ExitCode(code), message);
    });
    mpi.phase("composite", [] {});
    if (mpi.isRoot()) std::ofstream(outFile) << "frame\n";
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 5) {
        std::cerr << "usage: tubecast_mpi_fault barrier|abort FAIL_RANK CODE OUT_FILE\n";
        return 2;
    }
    try {
        return run(argv[1], std::stoi(argv[2]), std::stoi(argv[3]), argv[4]);
    } catch (const tc::cli::RankFailure& e) {
        return int(e.code());  // rank 0 printed the report
    } catch (const tc::Error& e) {
        std::cerr << "error: " << e.what() << "\n";
        tc::cli::MpiSession::abortIfLeftAlone(int(e.code()));
        return int(e.code());
    }
}
