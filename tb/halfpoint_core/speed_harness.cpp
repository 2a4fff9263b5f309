// SPDX-License-Identifier: Apache-2.0
// Compiled Verilator harness for halfpoint_core (NA=3, W=32, TW=16): the
// simulation-speed figure of `make bench`.  Reads a vector file written by
// model/halfpoint/flows/simspeed.py -- the commands and the model's expected moves
// (clock, positions) -- streams the commands with tvalid high whenever one is
// left (as the model's run_program does), and checks every move's clock and
// positions against the model.  Prints "clocks <n> seconds <s> moves <m>" and
// exits 1 on the first difference.
//
// usage: speed_harness <vectors> <repeats>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "Vhalfpoint_core.h"
#include "verilated.h"

struct Move {
    uint64_t cycle;
    int64_t pos[3];
};

static int32_t s32(uint32_t v) { return static_cast<int32_t>(v); }

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: %s <vectors> <repeats>\n", argv[0]);
        return 2;
    }
    FILE* f = std::fopen(argv[1], "r");
    if (!f) {
        std::perror(argv[1]);
        return 2;
    }
    const int repeats = std::atoi(argv[2]);
    size_t ncmd = 0, nmove = 0;
    if (std::fscanf(f, "%zu %zu", &ncmd, &nmove) != 2) return 2;
    std::vector<std::vector<uint32_t>> cmds(ncmd, std::vector<uint32_t>(8));
    for (size_t i = 0; i < ncmd; ++i) {
        char hex[65];
        if (std::fscanf(f, "%64s", hex) != 1) return 2;
        for (int w = 0; w < 8; ++w) {  // word 0 = least significant = last 8 hex digits
            char part[9];
            std::memcpy(part, hex + (7 - w) * 8, 8);
            part[8] = 0;
            cmds[i][w] = static_cast<uint32_t>(std::strtoul(part, nullptr, 16));
        }
    }
    std::vector<Move> expect(nmove);
    for (size_t i = 0; i < nmove; ++i) {
        Move& m = expect[i];
        if (std::fscanf(f, "%" SCNu64 " %" SCNd64 " %" SCNd64 " %" SCNd64, &m.cycle, &m.pos[0], &m.pos[1],
                        &m.pos[2]) != 4)
            return 2;
    }
    std::fclose(f);

    VerilatedContext ctx;
    Vhalfpoint_core top{&ctx};
    const uint64_t timing = 1;  // steplen 1, stepspace 1 clocks, dirsetup/dirhold 1 (the model's default)
    top.cfg_steplen = timing | (timing << 16) | (timing << 32);
    top.cfg_stepspace = top.cfg_steplen;
    top.cfg_dirsetup = top.cfg_steplen;
    top.cfg_dirhold = top.cfg_steplen;
    top.cfg_step_inv = 0;
    top.cfg_dir_inv = 0;
    top.feed_override = 128;
    top.hold = 0;
    top.stop = 0;
    top.abort_now = 0;

    uint64_t clocks = 0, moves = 0;
    auto tick = [&]() {
        top.clk = 0;
        top.eval();
        top.clk = 1;
        top.eval();
        ++clocks;
    };
    auto t0 = std::chrono::steady_clock::now();
    for (int r = 0; r < repeats; ++r) {
        top.rst = 1;
        top.s_axis_tvalid = 0;
        tick();
        top.rst = 0;
        size_t idx = 0, nm = 0;
        uint64_t cyc = 0;
        int idle = 0;
        while (idx < ncmd || idle < 4) {
            top.eval();
            if (top.move) {
                if (nm >= nmove) {
                    std::printf("FAIL: extra move at clock %" PRIu64 "\n", cyc);
                    return 1;
                }
                const Move& m = expect[nm];
                int64_t p[3] = {s32(top.pos[0]), s32(top.pos[1]), s32(top.pos[2])};
                if (m.cycle != cyc || p[0] != m.pos[0] || p[1] != m.pos[1] || p[2] != m.pos[2]) {
                    std::printf("FAIL: move %zu at clock %" PRIu64 " pos %" PRId64 " %" PRId64 " %" PRId64
                                ", model: clock %" PRIu64 " pos %" PRId64 " %" PRId64 " %" PRId64 "\n",
                                nm, cyc, p[0], p[1], p[2], m.cycle, m.pos[0], m.pos[1], m.pos[2]);
                    return 1;
                }
                ++nm;
            }
            bool busy = top.busy;
            if (idx < ncmd) {
                top.s_axis_tvalid = 1;
                for (int w = 0; w < 8; ++w) top.s_axis_tdata[w] = cmds[idx][w];
                if (top.s_axis_tready) ++idx;
            } else {
                top.s_axis_tvalid = 0;
            }
            idle = (busy || idx < ncmd) ? 0 : idle + 1;
            tick();
            ++cyc;
        }
        if (nm != nmove) {
            std::printf("FAIL: %zu moves, model %zu\n", nm, nmove);
            return 1;
        }
        moves += nm;
    }
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    top.final();
    std::printf("clocks %" PRIu64 " seconds %.6f moves %" PRIu64 "\n", clocks, s, moves);
    return 0;
}
