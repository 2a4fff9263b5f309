// SPDX-License-Identifier: Apache-2.0
// The virtual board of `halfpoint board-sim`: a compiled Verilator harness of
// rtl/halfpoint_uart_top.v that serves the board's serial port on a TCP port of
// 127.0.0.1.  Bytes from the TCP client are driven onto the simulated uart_rx
// pin bit by bit (8N1 at the board's bit rate, CLK_HZ / BAUD clocks a bit);
// the uart_tx pin is sampled at the middle of each bit and the bytes go back to
// the client.  Every axis's STEP/DIR pins are counted (a STEP rise moves the
// axis by +1 with DIR high, -1 with DIR low) and checked against the timing
// rules of model/halfpoint/sim/timing.py (STEP active exactly max(steplen, 1)
// clocks, inactive at least stepspace, DIR changes at least dirhold after a
// fall and at least dirsetup before a rise, never while STEP is active).
//
// On exit (SIGINT, SIGTERM, or --exit-when-idle: a client came and went and
// the board is idle) it prints, on stdout:
//     steps: <per axis: +rises -rises>
//     position: x,y,z              (BLU, the sum of the counted steps)
//     timing: ok | timing: <n> violations, first: <what>
//     clocks: <n>
// and exits 1 if a timing rule was broken, else 0.
//
// usage: boardsim_harness --port P --cpb N --axes N --steplen N --stepspace N
//                         --dirsetup N --dirhold N [--exit-when-idle]
// (port 0: any free port; the harness prints "listening on 127.0.0.1:<port>"
// first.)  The design's parameters are fixed when it is built
// (model/halfpoint/sim/boardsim.py passes the same values to both).
#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <unistd.h>

#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <string>
#include <vector>

#include "Vhalfpoint_uart_top.h"
#include "verilated.h"

static volatile std::sig_atomic_t quit_requested = 0;
static void on_signal(int) { quit_requested = 1; }

struct Axis {
    long steplen = 1, stepspace = 1, dirsetup = 1, dirhold = 1;
    long long position = 0, rises_up = 0, rises_down = 0;
    int prev_step = 0, prev_dir = -1;
    long long rise = -1, fall = -1, dir_change = -1;
};

struct Checker {
    long long violations = 0;
    std::string first;
    void fail(int axis, long long cycle, const std::string& what) {
        if (violations++ == 0)
            first = "axis " + std::to_string(axis) + ", cycle " + std::to_string(cycle) + ": " +
                    what;
    }
    void sample(Axis& a, int k, long long n, int step, int dir) {
        if (!step && a.prev_step) {
            long long width = n - a.rise;
            long need = a.steplen > 1 ? a.steplen : 1;
            if (width != need)
                fail(k, n, "steplen: STEP active " + std::to_string(width) + " clocks, need " +
                               std::to_string(need));
            a.fall = n;
        }
        if (a.prev_dir >= 0 && dir != a.prev_dir) {
            if (a.prev_step && step) fail(k, n, "DIR changed while STEP was active");
            if (a.fall >= 0 && n - a.fall < a.dirhold)
                fail(k, n, "dirhold: DIR changed " + std::to_string(n - a.fall) +
                               " clocks after STEP fell");
            a.dir_change = n;
        }
        if (step && !a.prev_step) {
            if (a.fall >= 0 && n - a.fall < a.stepspace)
                fail(k, n, "stepspace: STEP inactive " + std::to_string(n - a.fall) + " clocks");
            if (a.dir_change >= 0 && n - a.dir_change < a.dirsetup)
                fail(k, n, "dirsetup: STEP " + std::to_string(n - a.dir_change) +
                               " clocks after DIR changed");
            a.rise = n;
            if (dir) {
                a.position++;
                a.rises_up++;
            } else {
                a.position--;
                a.rises_down++;
            }
        }
        a.prev_step = step;
        a.prev_dir = dir;
    }
};

static long arg_value(int argc, char** argv, const char* name, long fallback) {
    for (int i = 1; i + 1 < argc; ++i)
        if (std::strcmp(argv[i], name) == 0) return std::strtol(argv[i + 1], nullptr, 0);
    return fallback;
}

static bool arg_flag(int argc, char** argv, const char* name) {
    for (int i = 1; i < argc; ++i)
        if (std::strcmp(argv[i], name) == 0) return true;
    return false;
}

int main(int argc, char** argv) {
    Verilated::commandArgs(1, argv);
    const long port = arg_value(argc, argv, "--port", 0);
    const long cpb = arg_value(argc, argv, "--cpb", 8);
    const int axes = static_cast<int>(arg_value(argc, argv, "--axes", 3));
    const bool exit_when_idle = arg_flag(argc, argv, "--exit-when-idle");
    if (cpb < 8 || axes < 1 || axes > 6 || port < 0 || port > 65535) {
        std::fprintf(stderr, "boardsim_harness: bad arguments\n");
        return 2;
    }
    std::vector<Axis> axis(axes);
    for (Axis& a : axis) {
        a.steplen = arg_value(argc, argv, "--steplen", 1);
        a.stepspace = arg_value(argc, argv, "--stepspace", 1);
        a.dirsetup = arg_value(argc, argv, "--dirsetup", 1);
        a.dirhold = arg_value(argc, argv, "--dirhold", 1);
    }
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    std::signal(SIGPIPE, SIG_IGN);

    int listener = socket(AF_INET, SOCK_STREAM, 0);
    int one = 1;
    setsockopt(listener, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (bind(listener, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
        listen(listener, 1) != 0) {
        std::fprintf(stderr, "boardsim_harness: cannot listen on 127.0.0.1:%ld: %s\n", port,
                     std::strerror(errno));
        return 2;
    }
    socklen_t len = sizeof addr;
    getsockname(listener, reinterpret_cast<sockaddr*>(&addr), &len);
    std::printf("listening on 127.0.0.1:%d\n", ntohs(addr.sin_port));
    std::fflush(stdout);

    Vhalfpoint_uart_top top;
    top.clk = 0;
    top.btn_reset = 0;
    top.btn_abort = 0;
    top.uart_rx = 1;
    top.eval();

    Checker checker;
    int client = -1;
    bool had_client = false;
    std::deque<uint8_t> to_board;       // bytes from the client, not yet on uart_rx
    std::vector<uint8_t> to_client;     // bytes from uart_tx, not yet sent
    // uart_rx driver: bit 0 start, 1..8 data, 9 stop; -1 idle
    int rx_bit = -1;
    long rx_count = 0;
    uint8_t rx_byte = 0;
    // uart_tx sampler
    int tx_bit = -1;
    long tx_count = 0;
    uint8_t tx_byte = 0;
    int tx_prev = 1;
    long long cycle = 0, quiet = 0;
    long long next_poll = 0;

    while (!quit_requested) {
        // ------------------------------------------------------------ network
        if (cycle >= next_poll) {
            const bool board_idle = !(top.led & 1) && rx_bit < 0 && tx_bit < 0 &&
                                    to_board.empty() && quiet > 64 * cpb;
            fd_set rd;
            FD_ZERO(&rd);
            FD_SET(listener, &rd);
            int maxfd = listener;
            if (client >= 0) {
                FD_SET(client, &rd);
                if (client > maxfd) maxfd = client;
            }
            timeval tv{0, board_idle ? 1000 : 0};
            if (select(maxfd + 1, &rd, nullptr, nullptr, &tv) > 0) {
                if (FD_ISSET(listener, &rd)) {
                    int c = accept(listener, nullptr, nullptr);
                    if (c >= 0 && client >= 0) {
                        close(c);       // one client at a time
                    } else if (c >= 0) {
                        client = c;
                        had_client = true;
                        setsockopt(client, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
                    }
                }
                if (client >= 0 && FD_ISSET(client, &rd)) {
                    uint8_t buf[4096];
                    ssize_t n = recv(client, buf, sizeof buf, 0);
                    if (n <= 0) {
                        close(client);
                        client = -1;
                        to_board.clear();
                    } else {
                        to_board.insert(to_board.end(), buf, buf + n);
                    }
                }
            }
            if (!to_client.empty()) {
                if (client >= 0) send(client, to_client.data(), to_client.size(), 0);
                to_client.clear();
            }
            if (exit_when_idle && had_client && client < 0 && board_idle) break;
            next_poll = cycle + (board_idle ? 4096 : 256);
        }

        // -------------------------------------------------------------- clock
        top.clk = 1;
        top.eval();
        // pins after the edge: one sample per clock
        const int step = top.step, dir = top.dir;
        for (int k = 0; k < axes; ++k)
            checker.sample(axis[k], k, cycle, (step >> k) & 1, (dir >> k) & 1);
        const bool moving = (top.led & 1) || step;
        quiet = moving ? 0 : quiet + 1;

        const int tx = top.uart_tx;
        if (tx_bit < 0) {
            if (tx_prev && !tx) {
                tx_bit = 0;
                tx_count = cpb / 2;     // to the middle of the start bit
            }
        } else if (--tx_count == 0) {
            if (tx_bit == 0) {
                tx_bit = tx ? -1 : 1;   // a glitch: back to idle
                tx_byte = 0;
            } else if (tx_bit <= 8) {
                tx_byte = static_cast<uint8_t>(tx_byte | (tx << (tx_bit - 1)));
                tx_bit++;
            } else {
                if (tx) to_client.push_back(tx_byte);   // a bad stop bit drops the byte
                tx_bit = -1;
            }
            if (tx_bit >= 0) tx_count = cpb;
        }
        tx_prev = tx;

        // uart_rx for the next clock
        if (rx_bit < 0 && !to_board.empty()) {
            rx_byte = to_board.front();
            to_board.pop_front();
            rx_bit = 0;
            rx_count = cpb;
        }
        if (rx_bit >= 0) {
            top.uart_rx = rx_bit == 0 ? 0 : rx_bit <= 8 ? (rx_byte >> (rx_bit - 1)) & 1 : 1;
            if (--rx_count == 0) {
                rx_count = cpb;
                if (++rx_bit > 9) rx_bit = -1;
            }
        } else {
            top.uart_rx = 1;
        }
        top.clk = 0;
        top.eval();
        cycle++;
    }
    if (client >= 0) close(client);
    close(listener);

    std::string steps, position;
    const char* names = "xyzabc";
    for (int k = 0; k < axes; ++k) {
        steps += (k ? ", " : "") + std::string(1, names[k]) + " +" +
                 std::to_string(axis[k].rises_up) + " -" + std::to_string(axis[k].rises_down);
        position += (k ? "," : "") + std::to_string(axis[k].position);
    }
    std::printf("steps: %s\n", steps.c_str());
    std::printf("position: %s\n", position.c_str());
    if (checker.violations)
        std::printf("timing: %lld violations, first: %s\n", checker.violations,
                    checker.first.c_str());
    else
        std::printf("timing: ok\n");
    std::printf("clocks: %lld\n", cycle);
    std::fflush(stdout);
    return checker.violations ? 1 : 0;
}
