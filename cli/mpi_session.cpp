#include "cli/mpi_session.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iostream>
#include <limits>
#include <new>

namespace tc::cli {

namespace {

// Message tags of the point-to-point transfers; each collective uses its own so that messages of
// consecutive operations between the same two ranks cannot be mistaken for each other.
enum Tag : int { kTagGather = 101, kTagScatter = 102, kTagExchange = 103 };

void checkMpi(int rc, const char* call) {
    if (rc == MPI_SUCCESS) return;
    char text[MPI_MAX_ERROR_STRING];
    int len = 0;
    MPI_Error_string(rc, text, &len);
    throw Error(ExitCode::Internal, std::string(call) + " failed: " + std::string(text, std::size_t(len)));
}

int chunkCount(std::size_t n, std::size_t chunk) {
    return int((n + chunk - 1) / chunk);
}

// "rank R (host H)" of an MpiSession destroyed by an error the other ranks do not know of; empty
// while there is none. Read by abortIfLeftAlone.
std::string g_leftAlone;

}  // namespace

MpiSession::MpiSession() {
    int initialised = 0;
    MPI_Initialized(&initialised);
    TC_CHECK(!initialised);
    int provided = 0;
    checkMpi(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided), "MPI_Init_thread");
    if (provided < MPI_THREAD_SERIALIZED) {
        MPI_Finalize();
        throw Error(ExitCode::Internal, "MPI_Init_thread: the MPI library does not provide MPI_THREAD_SERIALIZED");
    }
    // A communicator of our own: no message of ours can match a receive of a library that uses
    // MPI_COMM_WORLD (IceT duplicates the communicator it is given for the same reason).
    MPI_Comm_dup(MPI_COMM_WORLD, &m_comm);
    // Errors come back as codes (checkMpi turns them into exceptions) instead of ending the job
    // inside the library with no word of where.
    MPI_Comm_set_errhandler(m_comm, MPI_ERRORS_RETURN);
    MPI_Comm_rank(m_comm, &m_rank);
    MPI_Comm_size(m_comm, &m_size);
    m_uncaughtAtStart = std::uncaught_exceptions();

    char name[MPI_MAX_PROCESSOR_NAME] = {};
    int len = 0;
    MPI_Get_processor_name(name, &len);
    std::vector<char> all(std::size_t(m_size) * MPI_MAX_PROCESSOR_NAME);
    checkMpi(
        MPI_Allgather(name, MPI_MAX_PROCESSOR_NAME, MPI_CHAR, all.data(), MPI_MAX_PROCESSOR_NAME, MPI_CHAR, m_comm),
        "MPI_Allgather");
    for (int r = 0; r < m_size; ++r) {
        const char* s = &all[std::size_t(r) * MPI_MAX_PROCESSOR_NAME];
        m_hosts.emplace_back(s, strnlen(s, MPI_MAX_PROCESSOR_NAME));
    }
}

MpiSession::~MpiSession() {
    if (std::uncaught_exceptions() > m_uncaughtAtStart && !m_agreedFailure) {
        // MPI_Finalize would wait for ranks that wait for this one: leave MPI as it is; main()'s
        // error handler prints the error and then ends the job (abortIfLeftAlone).
        g_leftAlone = "rank " + std::to_string(m_rank) + " (host " + host() + ")";
        return;
    }
    MPI_Comm_free(&m_comm);
    MPI_Finalize();
}

void MpiSession::abortIfLeftAlone(int exitCode) {
    if (g_leftAlone.empty()) return;
    std::cerr << "error: " << g_leftAlone << " left the job with the error above; ending every rank" << std::endl;
    MPI_Abort(MPI_COMM_WORLD, exitCode == 0 ? int(ExitCode::Internal) : exitCode);
}

bool MpiSession::launchedByMpi() {
    // Open MPI's mpirun, PMIx (Open MPI 4+, srun --mpi=pmix), PMI-1/2 (MPICH's hydra,
    // srun --mpi=pmi2), MVAPICH.
    for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK", "MV2_COMM_WORLD_SIZE"}) {
        if (std::getenv(var)) return true;
    }
    return false;
}

PhaseResult MpiSession::attempt(const std::function<void()>& work) {
    try {
        work();
        return PhaseResult::success();
    } catch (const RankFailure&) {
        throw;  // already agreed on by every rank: not this rank's own failure
    } catch (const Error& e) {
        return PhaseResult::failure(int(e.code()), e.what());
    } catch (const std::bad_alloc&) {
        return PhaseResult::failure(int(ExitCode::Internal), "out of memory");
    } catch (const std::exception& e) {
        return PhaseResult::failure(int(ExitCode::Internal), std::string("internal error: ") + e.what());
    }
}

void MpiSession::barrier(std::string_view phase, const PhaseResult& mine) {
    std::vector<int> codes(static_cast<std::size_t>(m_size));
    int code = mine.exitCode;
    checkMpi(MPI_Allgather(&code, 1, MPI_INT, codes.data(), 1, MPI_INT, m_comm), "MPI_Allgather");
    std::vector<int> failed;
    for (int r = 0; r < m_size; ++r) {
        if (codes[std::size_t(r)] != 0) failed.push_back(r);
    }
    if (failed.empty()) {
        m_agreedFailure = false;
        return;
    }
    // Only failing ranks have something to say; the others send nothing.
    std::string_view text = mine.ok() ? std::string_view() : std::string_view(mine.message);
    std::vector<Bytes> messages = gatherBytes({reinterpret_cast<const std::uint8_t*>(text.data()), text.size()}, 0);
    m_agreedFailure = true;
    const ExitCode exitCode = ExitCode(codes[std::size_t(failed.front())]);
    // Built by appending: GCC 12's -Wrestrict misfires on "literal" + std::string temporaries
    // (GCC bug 105329).
    std::string where = "phase '";
    where.append(phase).append("'");
    if (m_rank != 0) {
        std::string summary = where;
        summary += " failed on rank";
        for (int r : failed) summary.append(" ").append(std::to_string(r));
        summary += " (reported by rank 0)";
        // Wait until rank 0 has printed: leaving first could make the launcher kill it mid-report.
        MPI_Barrier(m_comm);
        throw RankFailure(exitCode, summary);
    }
    auto appendLine = [&](std::string& out, int r) {
        const Bytes& m = messages[std::size_t(r)];
        out.append("rank ").append(std::to_string(r)).append(" (host ").append(m_hosts[std::size_t(r)]).append(")");
        if (failed.size() == 1) out.append(" in ").append(where);
        out.append(": ").append(m.begin(), m.end());
    };
    std::string report;
    if (failed.size() == 1) {
        appendLine(report, failed.front());
    } else {
        report.append(std::to_string(failed.size())).append(" ranks failed in ").append(where).append(":");
        for (int r : failed) {
            report += "\n  ";
            appendLine(report, r);
        }
    }
    // One write, so that the launcher's own messages cannot land inside the report.
    std::string printed = "error: ";
    printed.append(report).append("\n");
    std::cerr << printed << std::flush;
    MPI_Barrier(m_comm);
    throw RankFailure(exitCode, report);
}

void MpiSession::abort(int exitCode, std::string_view message) const {
    std::cerr << "error: rank " << m_rank << " (host " << host() << "): " << message << std::endl;
    MPI_Abort(MPI_COMM_WORLD, exitCode);
    std::_Exit(exitCode);  // MPI_Abort does not return; this only satisfies [[noreturn]]
}

// --- point to point, split into messages of at most m_chunkBytes --------------------------------

void MpiSession::sendChunked(const std::uint8_t* data, std::size_t n, int dest, int tag) const {
    for (std::size_t at = 0; at < n; at += m_chunkBytes) {
        int count = int(std::min(m_chunkBytes, n - at));
        checkMpi(MPI_Send(data + at, count, MPI_BYTE, dest, tag, m_comm), "MPI_Send");
    }
}

void MpiSession::recvChunked(std::uint8_t* data, std::size_t n, int source, int tag) const {
    for (std::size_t at = 0; at < n; at += m_chunkBytes) {
        int count = int(std::min(m_chunkBytes, n - at));
        checkMpi(MPI_Recv(data + at, count, MPI_BYTE, source, tag, m_comm, MPI_STATUS_IGNORE), "MPI_Recv");
    }
}

// --- collectives --------------------------------------------------------------------------------

std::vector<Bytes> MpiSession::gatherBytes(std::span<const std::uint8_t> mine, int root) const {
    std::uint64_t n = mine.size();
    std::vector<std::uint64_t> sizes(static_cast<std::size_t>(m_size));
    checkMpi(MPI_Gather(&n, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, root, m_comm), "MPI_Gather");
    if (m_rank != root) {
        sendChunked(mine.data(), mine.size(), root, kTagGather);
        return {};
    }
    std::vector<Bytes> all(static_cast<std::size_t>(m_size));
    for (int r = 0; r < m_size; ++r) {
        Bytes& b = all[std::size_t(r)];
        if (r == root) {
            b.assign(mine.begin(), mine.end());
        } else {
            b.resize(sizes[std::size_t(r)]);
            recvChunked(b.data(), b.size(), r, kTagGather);
        }
    }
    return all;
}

std::vector<nlohmann::json> MpiSession::gatherJson(const nlohmann::json& mine) const {
    std::vector<Bytes> parts = gatherBytes(nlohmann::json::to_cbor(mine), 0);
    std::vector<nlohmann::json> out;
    out.reserve(parts.size());
    for (const Bytes& p : parts) out.push_back(nlohmann::json::from_cbor(p));
    return out;
}

std::vector<std::vector<TimingRow>> MpiSession::gatherTimings(const std::vector<TimingRow>& mine) const {
    nlohmann::json rows = nlohmann::json::array();
    for (const TimingRow& r : mine) rows.push_back({r.frame, r.stage, r.gpuMs, r.cpuMs, r.items});
    std::vector<std::vector<TimingRow>> out;
    for (const nlohmann::json& rankRows : gatherJson(rows)) {
        std::vector<TimingRow>& list = out.emplace_back();
        for (const nlohmann::json& r : rankRows) {
            list.push_back({r[0].get<int>(), r[1].get<std::string>(), r[2].get<double>(), r[3].get<double>(),
                            r[4].get<std::uint64_t>()});
        }
    }
    return out;
}

void MpiSession::broadcastBytes(Bytes& buffer, int root) const {
    std::uint64_t n = buffer.size();
    checkMpi(MPI_Bcast(&n, 1, MPI_UINT64_T, root, m_comm), "MPI_Bcast");
    if (m_rank != root) buffer.resize(n);
    for (std::size_t at = 0; at < n; at += m_chunkBytes) {
        int count = int(std::min<std::size_t>(m_chunkBytes, n - at));
        checkMpi(MPI_Bcast(buffer.data() + at, count, MPI_BYTE, root, m_comm), "MPI_Bcast");
    }
}

Bytes MpiSession::scatterBytes(const std::vector<Bytes>& parts, int root) const {
    std::vector<std::uint64_t> sizes;
    if (m_rank == root) {
        TC_CHECK_OP(parts.size(), ==, std::size_t(m_size));
        for (const Bytes& p : parts) sizes.push_back(p.size());
    }
    std::uint64_t n = 0;
    checkMpi(MPI_Scatter(sizes.data(), 1, MPI_UINT64_T, &n, 1, MPI_UINT64_T, root, m_comm), "MPI_Scatter");
    if (m_rank != root) {
        Bytes mine(n);
        recvChunked(mine.data(), mine.size(), root, kTagScatter);
        return mine;
    }
    for (int r = 0; r < m_size; ++r) {
        if (r != root) sendChunked(parts[std::size_t(r)].data(), parts[std::size_t(r)].size(), r, kTagScatter);
    }
    return parts[std::size_t(root)];
}

std::vector<Bytes> MpiSession::exchangeBytes(const std::vector<Bytes>& outgoing) const {
    TC_CHECK_OP(outgoing.size(), ==, std::size_t(m_size));
    std::vector<std::uint64_t> sendSizes(static_cast<std::size_t>(m_size)), recvSizes(static_cast<std::size_t>(m_size));
    for (int r = 0; r < m_size; ++r) sendSizes[std::size_t(r)] = outgoing[std::size_t(r)].size();
    checkMpi(MPI_Alltoall(sendSizes.data(), 1, MPI_UINT64_T, recvSizes.data(), 1, MPI_UINT64_T, m_comm),
             "MPI_Alltoall");
    // Non-blocking sends and receives of every chunk, then one wait: MPI_Alltoallv's pattern
    // (Open MPI's basic algorithm posts the same), but with counts beyond int.
    std::vector<Bytes> incoming(static_cast<std::size_t>(m_size));
    std::vector<MPI_Request> requests;
    for (int r = 0; r < m_size; ++r) {
        if (r == m_rank) {
            incoming[std::size_t(r)] = outgoing[std::size_t(r)];
            continue;
        }
        Bytes& in = incoming[std::size_t(r)];
        in.resize(recvSizes[std::size_t(r)]);
        for (int c = 0; c < chunkCount(in.size(), m_chunkBytes); ++c) {
            std::size_t at = std::size_t(c) * m_chunkBytes;
            requests.emplace_back();
            checkMpi(MPI_Irecv(in.data() + at, int(std::min(m_chunkBytes, in.size() - at)), MPI_BYTE, r, kTagExchange,
                               m_comm, &requests.back()),
                     "MPI_Irecv");
        }
        const Bytes& out = outgoing[std::size_t(r)];
        for (int c = 0; c < chunkCount(out.size(), m_chunkBytes); ++c) {
            std::size_t at = std::size_t(c) * m_chunkBytes;
            requests.emplace_back();
            checkMpi(MPI_Isend(out.data() + at, int(std::min(m_chunkBytes, out.size() - at)), MPI_BYTE, r, kTagExchange,
                               m_comm, &requests.back()),
                     "MPI_Isend");
        }
    }
    checkMpi(MPI_Waitall(int(requests.size()), requests.data(), MPI_STATUSES_IGNORE), "MPI_Waitall");
    return incoming;
}

void MpiSession::allreduceSum(std::span<float> values) const {
    const std::size_t chunk = std::max<std::size_t>(1, m_chunkBytes / sizeof(float));
    for (std::size_t at = 0; at < values.size(); at += chunk) {
        int count = int(std::min(chunk, values.size() - at));
        checkMpi(MPI_Allreduce(MPI_IN_PLACE, values.data() + at, count, MPI_FLOAT, MPI_SUM, m_comm), "MPI_Allreduce");
    }
}

}  // namespace tc::cli
