// cli::MpiSession under N ranks: the fault barrier and the collectives of the data-parallel render.
#include <gtest/gtest.h>

#include <algorithm>
#include <new>
#include <numeric>
#include <stdexcept>

#include "mpi/mpi_test_session.h"

namespace tc::test {
namespace {

using cli::Bytes;
using cli::MpiSession;
using cli::PhaseResult;
using cli::RankFailure;

// Restores the default message size after a test that lowered it.
struct ChunkBytes {
    explicit ChunkBytes(std::size_t bytes) { mpi().setChunkBytes(bytes); }
    ~ChunkBytes() { mpi().setChunkBytes(std::size_t(1) << 30); }
};

Bytes pattern(int from, int to, std::size_t n) {
    Bytes b(n);
    for (std::size_t k = 0; k < n; ++k) b[k] = std::uint8_t(hash3(std::uint64_t(from), std::uint64_t(to), k));
    return b;
}

TEST(MpiSession, knows_every_rank_and_its_host) {
    MpiSession& s = mpi();
    EXPECT_GE(s.size(), 1);
    EXPECT_GE(s.rank(), 0);
    EXPECT_LT(s.rank(), s.size());
    ASSERT_EQ(s.hosts().size(), std::size_t(s.size()));
    for (const std::string& h : s.hosts()) EXPECT_FALSE(h.empty());
    EXPECT_EQ(s.host(), s.hosts()[std::size_t(s.rank())]);
    EXPECT_TRUE(MpiSession::launchedByMpi());
}

TEST(MpiSession, attempt_turns_exceptions_into_exit_codes_and_messages) {
    PhaseResult ok = MpiSession::attempt([] {});
    EXPECT_TRUE(ok.ok());
    PhaseResult output = MpiSession::attempt([] { throw OutputError("out/f.png: cannot write: disk full"); });
    EXPECT_EQ(output.exitCode, int(ExitCode::CannotWrite));
    EXPECT_EQ(output.message, "out/f.png: cannot write: disk full");
    PhaseResult memory = MpiSession::attempt([] { throw std::bad_alloc(); });
    EXPECT_EQ(memory.exitCode, int(ExitCode::Internal));
    EXPECT_EQ(memory.message, "out of memory");
    PhaseResult other = MpiSession::attempt([] { throw std::runtime_error("boom"); });
    EXPECT_EQ(other.exitCode, int(ExitCode::Internal));
    EXPECT_EQ(other.message, "internal error: boom");
}

TEST(MpiSession, barrier_passes_when_every_rank_succeeded) {
    EXPECT_NO_THROW(mpi().barrier("load", PhaseResult::success()));
    int calls = 0;
    EXPECT_NO_THROW(mpi().phase("render", [&] { ++calls; }));
    EXPECT_EQ(calls, 1);
}

TEST(MpiSession, barrier_makes_every_rank_throw_the_failing_ranks_code_and_rank_0_report_it) {
    MpiSession& s = mpi();
    const int failing = s.size() - 1;
    PhaseResult mine = s.rank() == failing
                           ? PhaseResult::failure(int(ExitCode::InvalidInput), "data.tcb: brick 3 truncated")
                           : PhaseResult::success();
    bool thrown = false;
    try {
        s.barrier("load", mine);
    } catch (const RankFailure& e) {
        thrown = true;
        EXPECT_EQ(e.code(), ExitCode::InvalidInput);
        if (s.isRoot()) {
            EXPECT_EQ(std::string(e.what()), "rank " + std::to_string(failing) + " (host " +
                                                 s.hosts()[std::size_t(failing)] +
                                                 ") in phase 'load': data.tcb: brick 3 truncated");
        } else {
            EXPECT_EQ(std::string(e.what()),
                      "phase 'load' failed on rank " + std::to_string(failing) + " (reported by rank 0)");
        }
    }
    EXPECT_TRUE(thrown);
}

TEST(MpiSession, barrier_reports_every_failing_rank_with_the_lowest_ranks_code) {
    MpiSession& s = mpi();
    // Every odd rank fails (rank 0 too with one rank), each with its own code.
    const bool fails = s.size() == 1 || s.rank() % 2 == 1;
    const int code = s.rank() == 0 ? 3 : 4 + s.rank();
    std::vector<int> failing;
    for (int r = 0; r < s.size(); ++r) {
        if (s.size() == 1 || r % 2 == 1) failing.push_back(r);
    }
    std::string what;
    ExitCode got = ExitCode::Ok;
    try {
        s.phase("render", [&] {
            if (fails) throw Error(ExitCode(code), "failure of rank " + std::to_string(s.rank()));
        });
    } catch (const RankFailure& e) {
        what = e.what();
        got = e.code();
    }
    EXPECT_EQ(int(got), failing.front() == 0 ? 3 : 4 + failing.front());
    if (s.isRoot()) {
        for (int r : failing) {
            const std::string phase = failing.size() == 1 ? " in phase 'render'" : "";
            EXPECT_NE(what.find("rank " + std::to_string(r) + " (host " + s.hosts()[std::size_t(r)] + ")" + phase +
                                ": failure of rank " + std::to_string(r)),
                      std::string::npos)
                << what;
        }
        if (failing.size() > 1) {
            EXPECT_EQ(what.rfind(std::to_string(failing.size()) + " ranks failed in phase 'render':", 0), 0u) << what;
        }
    }
}

TEST(MpiSession, gathers_byte_buffers_of_any_size_in_chunks) {
    MpiSession& s = mpi();
    ChunkBytes small(7);
    Bytes mine = pattern(s.rank(), -1, std::size_t(s.rank() * 13 % 29));  // rank 0 sends nothing
    std::vector<Bytes> all = s.gatherBytes(mine, 0);
    std::vector<Bytes> atLast = s.gatherBytes(mine, s.size() - 1);
    if (s.isRoot()) {
        ASSERT_EQ(all.size(), std::size_t(s.size()));
        for (int r = 0; r < s.size(); ++r) EXPECT_EQ(all[std::size_t(r)], pattern(r, -1, std::size_t(r * 13 % 29)));
    } else {
        EXPECT_TRUE(all.empty());
    }
    if (s.rank() == s.size() - 1) {
        ASSERT_EQ(atLast.size(), std::size_t(s.size()));
        for (int r = 0; r < s.size(); ++r) EXPECT_EQ(atLast[std::size_t(r)], pattern(r, -1, std::size_t(r * 13 % 29)));
    }
}

TEST(MpiSession, gathers_json_and_timing_rows_exactly) {
    MpiSession& s = mpi();
    const double exact = 0.1 + 1e-16 * s.rank();
    std::vector<nlohmann::json> json = s.gatherJson({{"rank", s.rank()}, {"host", s.host()}, {"x", exact}});
    std::vector<TimingRow> rows = {{7, "render", 1.25 + s.rank(), 0.1 + 1e-16 * s.rank(), 12345678901234ull},
                                   {7, "composite", -1.0, 3.0 / (s.rank() + 1), 0}};
    std::vector<std::vector<TimingRow>> timings = s.gatherTimings(rows);
    if (!s.isRoot()) {
        EXPECT_TRUE(json.empty());
        EXPECT_TRUE(timings.empty());
        return;
    }
    ASSERT_EQ(json.size(), std::size_t(s.size()));
    ASSERT_EQ(timings.size(), std::size_t(s.size()));
    for (int r = 0; r < s.size(); ++r) {
        EXPECT_EQ(json[std::size_t(r)]["rank"], r);
        EXPECT_EQ(json[std::size_t(r)]["host"], s.hosts()[std::size_t(r)]);
        EXPECT_EQ(json[std::size_t(r)]["x"].get<double>(), 0.1 + 1e-16 * r);
        const std::vector<TimingRow>& t = timings[std::size_t(r)];
        ASSERT_EQ(t.size(), 2u);
        EXPECT_EQ(t[0].frame, 7);
        EXPECT_EQ(t[0].stage, "render");
        EXPECT_EQ(t[0].gpuMs, 1.25 + r);
        EXPECT_EQ(t[0].cpuMs, 0.1 + 1e-16 * r);
        EXPECT_EQ(t[0].items, 12345678901234ull);
        EXPECT_EQ(t[1].stage, "composite");
        EXPECT_EQ(t[1].gpuMs, -1.0);
        EXPECT_EQ(t[1].cpuMs, 3.0 / (r + 1));
    }
}

TEST(MpiSession, broadcasts_a_byte_buffer_in_chunks) {
    MpiSession& s = mpi();
    ChunkBytes small(5);
    const int root = s.size() - 1;
    Bytes buffer = s.rank() == root ? pattern(root, 99, 1003) : Bytes(3, 0xAB);
    s.broadcastBytes(buffer, root);
    EXPECT_EQ(buffer, pattern(root, 99, 1003));
}

TEST(MpiSession, scatters_one_part_to_each_rank) {
    MpiSession& s = mpi();
    ChunkBytes small(4);
    for (int root : {0, s.size() - 1}) {
        std::vector<Bytes> parts;
        if (s.rank() == root) {
            for (int r = 0; r < s.size(); ++r) parts.push_back(pattern(root, r, std::size_t(r * 9 + 2)));
        }
        Bytes mine = s.scatterBytes(parts, root);
        EXPECT_EQ(mine, pattern(root, s.rank(), std::size_t(s.rank() * 9 + 2))) << "root " << root;
    }
}

TEST(MpiSession, exchanges_byte_buffers_between_all_pairs) {
    MpiSession& s = mpi();
    ChunkBytes small(4);
    auto size = [](int from, int to) { return std::size_t((from * 7 + to * 3) % 11); };  // some empty
    std::vector<Bytes> outgoing;
    for (int to = 0; to < s.size(); ++to) outgoing.push_back(pattern(s.rank(), to, size(s.rank(), to)));
    std::vector<Bytes> incoming = s.exchangeBytes(outgoing);
    ASSERT_EQ(incoming.size(), std::size_t(s.size()));
    for (int from = 0; from < s.size(); ++from) {
        EXPECT_EQ(incoming[std::size_t(from)], pattern(from, s.rank(), size(from, s.rank()))) << "from " << from;
    }
}

TEST(MpiSession, allreduce_sums_a_float_vector_on_every_rank) {
    MpiSession& s = mpi();
    ChunkBytes small(12);  // 3 floats per MPI_Allreduce: 34 values take 12 calls
    std::vector<float> v(34);
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = float(s.rank() + 1) * 0.5f + float(i);  // sums are exact
    s.allreduceSum(v);
    const float ranks = float(s.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
        EXPECT_EQ(v[i], 0.5f * ranks * (ranks + 1) / 2 + ranks * float(i)) << i;
    }
}

}  // namespace
}  // namespace tc::test
