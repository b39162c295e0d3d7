// main() of tubecast_mpi_tests, run under mpiexec with N ranks (tests/mpi/CMakeLists.txt): one
// MpiSession for the whole run, every rank runs every test in the same order. Tests do their
// collectives first and assert afterwards, so a failed assertion on one rank cannot leave the others
// waiting in a collective. Rank 0 prints gtest's usual output; the other ranks print only their
// failures, prefixed with the rank. The exit code is non-zero if any rank failed.
#include <gtest/gtest.h>

#include <iostream>

#include "mpi/mpi_test_session.h"

namespace tc::test {

namespace {
cli::MpiSession* g_mpi = nullptr;

// The other ranks' failures, one line each (gtest's own printer would repeat every test's name
// N times).
class RankFailurePrinter : public ::testing::EmptyTestEventListener {
public:
    explicit RankFailurePrinter(int rank) : m_rank(rank) {}
    void OnTestPartResult(const ::testing::TestPartResult& result) override {
        if (!result.failed()) return;
        const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
        std::cerr << "[rank " << m_rank << "] FAILED " << (test ? test->test_suite_name() : "") << "."
                  << (test ? test->name() : "") << " at " << (result.file_name() ? result.file_name() : "?") << ":"
                  << result.line_number() << ": " << result.summary() << std::endl;
    }

private:
    int m_rank;
};
}  // namespace

cli::MpiSession& mpi() {
    return *g_mpi;
}

}  // namespace tc::test

int main(int argc, char** argv) {
    ::testing::InitGoogleTest(&argc, argv);
    tc::cli::MpiSession mpi;
    tc::test::g_mpi = &mpi;
    if (!mpi.isRoot()) {
        auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
        delete listeners.Release(listeners.default_result_printer());
        listeners.Append(new tc::test::RankFailurePrinter(mpi.rank()));
    } else {
        std::cout << "tubecast_mpi_tests: " << mpi.size() << " rank(s)" << std::endl;
    }
    int failed = RUN_ALL_TESTS() != 0 ? 1 : 0;
    int anyFailed = 0;
    MPI_Allreduce(&failed, &anyFailed, 1, MPI_INT, MPI_MAX, mpi.comm());
    if (mpi.isRoot() && anyFailed && !failed) std::cerr << "tests failed on another rank (see above)" << std::endl;
    return anyFailed;
}
