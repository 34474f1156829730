// raytracer-mpi's messages (see raytracer_mpi.cpp for the protocol): the tags, the
// headers that travel in front of a tile's float sums, and the polling wait. Included
// by raytracer_mpi.cpp only, like worker.h and coordinator.h: the program's parts, one
// translation unit.
#pragma once

#include <mpi.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <list>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "adaptive.h"
#include "cli.h"
#include "image_io.h"
#include "model.h"
#include "scene_parser.h"
#include "schedule.h"
#include "status.h"
#include "tile_pool.h"
#include "world.h"

namespace rtmpi {
namespace {


using Clock = std::chrono::steady_clock;

constexpr int kTagAssign = 1;  // rank 0 -> worker: AssignHeader [+ prior sums]
constexpr int kTagResult = 2;  // worker -> rank 0: ResultHeader + sums
// Tiles out at a worker at once: while it renders one, the next ones wait in its
// queue, so neither the round trip to rank 0 nor rank 0's poll period idles it. 3
// covers tiles that take less than a poll period on a many-core worker; more would
// only lengthen the wait for the last tiles.
constexpr int kDepth = 3;
constexpr int kLocalDepth = 2;  // tiles queued in rank 0's own pool
// Sleep between polls of MPI. Open MPI's blocking calls spin a core; sleeping instead
// leaves the cores to the render threads. A thread waiting for its pool wakes as soon
// as a tile is done; the period bounds how late a message from another rank is seen.
constexpr std::chrono::microseconds kPoll{200};

int g_rank = 0, g_size = 1;

// --- MPI errors --------------------------------------------------------------------

[[noreturn]] void fail(int status, const std::string& message) {
    std::cerr << "raytracer-mpi: rank " << g_rank << ": " << message << "; nothing written\n" << std::flush;
    MPI_Abort(MPI_COMM_WORLD, status);  // ends every rank of the job
    std::_Exit(status);                 // MPI_Abort does not return; in case it does
}

void check(int rc, const char* what) {
    if (rc == MPI_SUCCESS) return;
    char text[MPI_MAX_ERROR_STRING];
    int len = 0;
    if (MPI_Error_string(rc, text, &len) != MPI_SUCCESS) len = std::snprintf(text, sizeof text, "error %d", rc);
    fail(kExitMpi, std::string("MPI error in ") + what + ": " + std::string(text, std::size_t(len)));
}

// Size in bytes of a received message.
int received_bytes(const MPI_Status& status) {
    int n = 0;
    check(MPI_Get_count(&status, MPI_BYTE, &n), "MPI_Get_count");
    return n;
}

// --- messages ----------------------------------------------------------------------
// Headers travel as bytes in front of the float sums, in one message per tile. The
// ranks are assumed to share byte order and float format (one architecture), as MPI
// jobs built from one binary do.

struct JobHeader {
    std::int32_t status = -1;  // -1: render; else every rank exits with this status
    std::int32_t width = 0, height = 0;
    std::int32_t max_samples = 1, samples_per_pass = 0;
    std::int32_t threads = 0, max_depth = rt::kDefaultMaxDepth, tile = rt::kDefaultTile, mirror = 0;
    std::int32_t pad = 0;  // no uninitialised padding goes on the wire
    double time_limit = 0;
    double aa_threshold = -1;
    std::uint64_t text_size = 0;
};

// A refine assignment (refine >= 0, the round) carries per pixel of the tile its sums,
// its squares and its sample counts from and to (RefineIn); its result, the sums and
// the squares. Otherwise: the sums of the earlier passes, if any, and back the sums.
struct AssignHeader {
    std::int32_t tile = -1;  // -1: stop
    std::int32_t s0 = 0, s1 = 0;
    std::int32_t has_prior = 0;  // the tile's sums of samples [0, s0) follow
    std::int32_t refine = -1;
    std::int32_t pad = 0;
};

struct ResultHeader {
    std::int32_t tile = -1;
    std::int32_t s0 = 0, s1 = 0;
    std::int32_t refine = -1;
    std::uint64_t rays = 0;
};

// Floats a tile of n pixels travels as: an assignment's payload, a result's.
std::size_t assign_floats(const AssignHeader& a, std::size_t n) {
    return a.refine >= 0 ? 6 * n : a.has_prior ? 3 * n : 0;
}
std::size_t result_floats(int refine, std::size_t n) { return refine >= 0 ? 4 * n : 3 * n; }

// Floats taken by a header at the front of a float buffer (keeps the sums aligned).
template <class H>
constexpr std::size_t head_floats() {
    return (sizeof(H) + sizeof(float) - 1) / sizeof(float);
}

template <class H>
void put_header(std::vector<float>& buf, const H& h) {
    std::memcpy(static_cast<void*>(buf.data()), static_cast<const void*>(&h), sizeof h);
}

template <class H>
H get_header(const std::vector<float>& buf) {
    H h;
    std::memcpy(static_cast<void*>(&h), static_cast<const void*>(buf.data()), sizeof h);
    return h;
}

int bytes_of(std::size_t floats) { return int(floats * sizeof(float)); }

// Waits for a request by polling, so a waiting rank does not spin a core.
void wait_polling(MPI_Request& req, MPI_Status* status, const char* what) {
    for (;;) {
        int done = 0;
        check(MPI_Test(&req, &done, status ? status : MPI_STATUS_IGNORE), what);
        if (done) return;
        std::this_thread::sleep_for(kPoll);
    }
}

}  // namespace
}  // namespace rtmpi
