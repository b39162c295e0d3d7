#pragma once
// The MPI side of a data-parallel render (`tubecast render --mpi`): one MpiSession per process
// (MPI_Init_thread ... MPI_Finalize), the fault barrier that makes every rank agree whether a phase
// succeeded, and the collectives the render needs: timings and run.json parts gathered to rank 0,
// byte buffers broadcast, scattered and exchanged (the data distribution), and the summed density
// grid of ambient occlusion. Every member function except the accessors is collective: all ranks
// call it, in the same order, with matching arguments.
//
// Failure protocol. A rank's work between two barriers is a phase; run it through attempt(), which
// turns an exception into a PhaseResult (the error's exit code and message), and then call
// barrier() with it on every rank. If any rank failed, rank 0 prints a report naming each failing
// rank, its host and its error, and barrier() throws RankFailure on every rank with the exit code
// of the lowest failing rank. Outputs are written only after the barrier that follows the composite,
// so a failed job leaves no partial frame. A rank that leaves with an exception outside this
// protocol cannot meet the others in their next collective: MpiSession's destructor notices it
// (the stack unwinds through it with anything but a RankFailure) and leaves MPI initialised, and
// the error handler of main(), after printing the error, calls MpiSession::abortIfLeftAlone, which
// ends every rank of the job with MPI_Abort and the error's exit code. abort() is the same last
// resort, called on purpose.
//
// Counts. MPI counts are `int`; buffers here may be larger (a rank's share of a 10^9-segment set),
// so the byte transfers are split into messages of at most `chunkBytes` (the library cannot do
// this itself before MPI 4's large-count functions, which Open MPI 4.1 does not have).
#include <mpi.h>

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.h"
#include "io/timings_csv.h"

namespace tc::cli {

using Bytes = std::vector<std::uint8_t>;

// What one rank reports at a barrier: success, or its error's exit code and message.
struct PhaseResult {
    int exitCode = 0;  // 0 = ok
    std::string message;

    bool ok() const { return exitCode == 0; }
    static PhaseResult success() { return {}; }
    static PhaseResult failure(int exitCode, std::string message) { return {exitCode, std::move(message)}; }
};

// Thrown by MpiSession::barrier on every rank when a phase failed on at least one rank. code() is
// the lowest failing rank's exit code. Rank 0 has already printed the report when this is thrown
// ("error: rank 2 (host node7) in phase 'load': scene.tcb: ...", a line per failing rank), before
// any rank could exit: a launcher that sees one rank exit non-zero kills the others, rank 0 with
// its unprinted message among them. So whoever catches it prints nothing more. On rank 0 what()
// is that report (without "error: "); on the others a one-line summary.
class RankFailure : public Error {
public:
    using Error::Error;
};

class MpiSession {
public:
    // Initialises MPI (MPI_Init_thread with MPI_THREAD_SERIALIZED: the renderer's worker threads
    // never call MPI, but the frame writer's thread may run while the main thread is in MPI) and
    // learns every rank's host name. Throws Error(Internal) if MPI is already initialised or
    // cannot provide that thread level. Works without a launcher too (a singleton of size 1).
    MpiSession();
    // MPI_Finalize; but when the stack unwinds through it with an exception the ranks have not
    // agreed on (anything but RankFailure), MPI stays initialised for abortIfLeftAlone.
    ~MpiSession();
    MpiSession(const MpiSession&) = delete;
    MpiSession& operator=(const MpiSession&) = delete;

    // True when the process was started by an MPI launcher (mpirun/mpiexec, or srun with PMI/PMIx),
    // judged from the launcher's environment variables; for warning about a render under mpirun
    // without --mpi, where every rank would render and write the whole frame.
    static bool launchedByMpi();

    int rank() const { return m_rank; }
    int size() const { return m_size; }
    bool isRoot() const { return m_rank == 0; }
    const std::string& host() const { return m_hosts[std::size_t(m_rank)]; }
    const std::vector<std::string>& hosts() const { return m_hosts; }  // index = rank
    MPI_Comm comm() const { return m_comm; }

    // --- faults ------------------------------------------------------------------------------
    // Runs `work`; an exception becomes a failed PhaseResult: tc::Error with its code,
    // std::bad_alloc as "out of memory" (Internal), any other std::exception as Internal.
    static PhaseResult attempt(const std::function<void()>& work);
    // Collective. Every rank learns whether any rank's `mine` failed; if so, rank 0 prints the
    // failing ranks' messages to stderr and every rank throws RankFailure (see there). The
    // messages travel to rank 0 only.
    void barrier(std::string_view phase, const PhaseResult& mine);
    // attempt(work) then barrier(phase, ...).
    void phase(std::string_view phase, const std::function<void()>& work) { barrier(phase, attempt(work)); }
    // The last resort for a rank that cannot reach the next collective: prints
    // "error: rank R (host H): message" and ends every rank of the job (MPI_Abort). Does not return.
    [[noreturn]] void abort(int exitCode, std::string_view message) const;
    // For main()'s error handler, after it printed the error: if an MpiSession was destroyed by that
    // error (see the class comment), prints "error: rank R (host H) left the job with the error
    // above; ending every rank" and calls MPI_Abort(exitCode). Otherwise does nothing.
    static void abortIfLeftAlone(int exitCode);

    // --- collectives -------------------------------------------------------------------------
    // Rank `root` gets every rank's buffer (index = rank); the others get an empty vector.
    std::vector<Bytes> gatherBytes(std::span<const std::uint8_t> mine, int root = 0) const;
    // Rank 0 gets every rank's JSON (index = rank; carried as CBOR, so numbers round-trip exactly).
    std::vector<nlohmann::json> gatherJson(const nlohmann::json& mine) const;
    // Rank 0 gets every rank's timing rows (index = rank), e.g. for timings.csv's rank column.
    std::vector<std::vector<TimingRow>> gatherTimings(const std::vector<TimingRow>& mine) const;
    // `buffer` of rank `root` is copied to every rank (resized there).
    void broadcastBytes(Bytes& buffer, int root = 0) const;
    // Rank `root` sends parts[r] to rank r (parts has size() entries there; ignored elsewhere);
    // every rank returns its part.
    Bytes scatterBytes(const std::vector<Bytes>& parts, int root = 0) const;
    // All-to-all: outgoing[r] (size() entries) goes to rank r; returns incoming[r] from rank r.
    std::vector<Bytes> exchangeBytes(const std::vector<Bytes>& outgoing) const;
    // Element-wise sum over ranks, in place, the same result on every rank (MPI_Allreduce).
    void allreduceSum(std::span<float> values) const;

    // Largest message the byte transfers send (default 1 GiB); tests lower it to exercise the
    // splitting on small buffers.
    void setChunkBytes(std::size_t bytes) { m_chunkBytes = bytes; }

private:
    void sendChunked(const std::uint8_t* data, std::size_t n, int dest, int tag) const;
    void recvChunked(std::uint8_t* data, std::size_t n, int source, int tag) const;

    MPI_Comm m_comm = MPI_COMM_NULL;
    int m_rank = 0;
    int m_size = 1;
    int m_uncaughtAtStart = 0;
    bool m_agreedFailure = false;  // a RankFailure is on its way out: finalise, do not abort
    std::size_t m_chunkBytes = std::size_t(1) << 30;
    std::vector<std::string> m_hosts;
};

}  // namespace tc::cli
