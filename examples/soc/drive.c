/* SPDX-License-Identifier: Apache-2.0 */
/*
 * drive.c: driving the halfpoint motion core from C through its registers
 * (halfpoint_wb or halfpoint_axil), with the generated header
 * include/halfpoint_regs.h.
 *
 * The program pushes a list of 256-bit commands (eight 32-bit words each, as
 * the host toolchain encodes them: a PROFILE before every motion command),
 * waiting for room in the queue, reads the positions of all axes coherently
 * while the machine moves, and waits for the end of the program.
 *
 *   bare metal:  cc -DHALFPOINT_BASE=0xf0000000 ... (the slave's base address);
 *                halfpoint_run(commands, count) from your own main
 *   hosted demo: cc -DHALFPOINT_PIPE -Iinclude -o drive examples/soc/drive.c
 *                ./drive program.hex
 *                program.hex: one command per line, eight hex words, word 0
 *                first.  With HALFPOINT_PIPE every register access is a line on
 *                stdout ("R <offset>" or "W <offset> <value>", hex) answered by
 *                a line on stdin ("<ok> <value>"): tb/halfpoint_regs runs the
 *                RTL behind it.  Messages go to stderr.
 */
#include <stdint.h>
#include <stdio.h>

#include "halfpoint_regs.h"

/* ------------------------------------------------------------------ access */

#ifdef HALFPOINT_PIPE
static uint32_t pipe_access(char kind, uint32_t offset, uint32_t value)
{
    unsigned ok = 0, answer = 0;
    if (kind == 'R')
        printf("R %x\n", (unsigned)offset);
    else
        printf("W %x %x\n", (unsigned)offset, (unsigned)value);
    fflush(stdout);
    if (scanf("%u %x", &ok, &answer) != 2 || !ok) {
        fprintf(stderr, "drive: bus error at offset 0x%02x\n", (unsigned)offset);
        return 0;
    }
    return (uint32_t)answer;
}

static uint32_t reg_read(uint32_t offset)
{
    return pipe_access('R', offset, 0u);
}

static void reg_write(uint32_t offset, uint32_t value)
{
    (void)pipe_access('W', offset, value);
}
#else
#ifndef HALFPOINT_BASE
#define HALFPOINT_BASE 0xf0000000u
#endif
static uint32_t reg_read(uint32_t offset)
{
    return *(volatile uint32_t *)(uintptr_t)(HALFPOINT_BASE + offset);
}

static void reg_write(uint32_t offset, uint32_t value)
{
    *(volatile uint32_t *)(uintptr_t)(HALFPOINT_BASE + offset) = value;
}
#endif

/* ------------------------------------------------------------------ driver */

/* 0 when the slave is a halfpoint core of this register map's major version */
int halfpoint_probe(unsigned *axes)
{
    if (reg_read(HALFPOINT_ID) != HALFPOINT_ID_VALUE)
        return -1;
    if (HALFPOINT_GET(reg_read(HALFPOINT_VERSION), VERSION_MAJOR) != HALFPOINT_VERSION_MAJOR)
        return -1;
    *axes = HALFPOINT_GET(reg_read(HALFPOINT_GEOMETRY), GEOMETRY_AXES);
    return 0;
}

/* STEP/DIR timing of one axis, in clocks */
void halfpoint_timing(unsigned axis, uint32_t steplen, uint32_t stepspace,
                      uint32_t dirsetup, uint32_t dirhold)
{
    reg_write(HALFPOINT_STEP_TIMING(axis),
              HALFPOINT_PUT(STEP_TIMING_STEPLEN, steplen) |
              HALFPOINT_PUT(STEP_TIMING_STEPSPACE, stepspace));
    reg_write(HALFPOINT_DIR_TIMING(axis),
              HALFPOINT_PUT(DIR_TIMING_DIRSETUP, dirsetup) |
              HALFPOINT_PUT(DIR_TIMING_DIRHOLD, dirhold));
}

/* push one command, waiting for room; -1 if the core refused it */
int halfpoint_push(const uint32_t words[HALFPOINT_CMD_WORDS])
{
    unsigned k;
    while (HALFPOINT_GET(reg_read(HALFPOINT_QUEUE), QUEUE_FREE) == 0u)
        ;   /* or sleep until the QUEUE_LOW interrupt */
    for (k = 0; k < HALFPOINT_CMD_WORDS; k++)
        reg_write(HALFPOINT_CMD(k), words[k]);   /* CMD_7 pushes */
    if (reg_read(HALFPOINT_IRQ_STATUS) & HALFPOINT_IRQ_STATUS_OVERFLOW_MASK) {
        reg_write(HALFPOINT_IRQ_STATUS, HALFPOINT_IRQ_STATUS_OVERFLOW_MASK);
        return -1;
    }
    return 0;
}

/* all axes at one instant: POS_0 takes the snapshot that POS_1.. read */
void halfpoint_positions(int32_t *pos, unsigned axes)
{
    unsigned k;
    for (k = 0; k < axes; k++)
        pos[k] = (int32_t)reg_read(HALFPOINT_POS(k));
}

/* wait for the end of the program (polling; an interrupt handler would
 * wait for irq with IRQ_ENABLE.DONE set instead) */
void halfpoint_wait_done(void)
{
    reg_write(HALFPOINT_IRQ_STATUS, HALFPOINT_IRQ_STATUS_DONE_MASK);
    if (!(reg_read(HALFPOINT_STATUS) & HALFPOINT_STATUS_BUSY_MASK))
        return;
    while (!(reg_read(HALFPOINT_IRQ_STATUS) & HALFPOINT_IRQ_STATUS_DONE_MASK))
        ;
}

static void print_positions(const char *what, const int32_t *pos, unsigned axes)
{
    unsigned k;
    fprintf(stderr, "%s", what);
    for (k = 0; k < axes; k++)
        fprintf(stderr, " %ld", (long)pos[k]);
    fprintf(stderr, "\n");
}

/* run a whole program; returns the code of the last rejected command (0: none),
 * or -1 for no halfpoint core or a refused push */
int halfpoint_run(const uint32_t (*commands)[HALFPOINT_CMD_WORDS], unsigned count)
{
    int32_t pos[HALFPOINT_MAX_AXES];
    unsigned axes, k;
    if (halfpoint_probe(&axes) != 0) {
        fprintf(stderr, "drive: no halfpoint core\n");
        return -1;
    }
    for (k = 0; k < axes; k++)
        halfpoint_timing(k, 2u, 2u, 1u, 1u);
    reg_write(HALFPOINT_CONTROL, HALFPOINT_PUT(CONTROL_OVERRIDE, 128u));
    for (k = 0; k < count; k++) {
        if (halfpoint_push(commands[k]) != 0) {
            fprintf(stderr, "drive: command %u refused\n", k);
            return -1;
        }
        if (k % 4u == 3u) {
            halfpoint_positions(pos, axes);
            print_positions("moving", pos, axes);
        }
    }
    halfpoint_wait_done();
    halfpoint_positions(pos, axes);
    print_positions("final", pos, axes);
    return (int)HALFPOINT_GET(reg_read(HALFPOINT_STATUS), STATUS_ERR_CODE);
}

/* ------------------------------------------------------------------ demo */

#ifdef HALFPOINT_PIPE
#define MAX_COMMANDS 256

int main(int argc, char **argv)
{
    static uint32_t commands[MAX_COMMANDS][HALFPOINT_CMD_WORDS];
    unsigned count = 0, k;
    int code;
    FILE *in;
    if (argc != 2) {
        fprintf(stderr, "usage: drive program.hex\n");
        return 2;
    }
    in = fopen(argv[1], "r");
    if (in == NULL) {
        perror(argv[1]);
        return 2;
    }
    for (;;) {
        unsigned long word;
        for (k = 0; k < HALFPOINT_CMD_WORDS; k++) {
            if (fscanf(in, "%lx", &word) != 1)
                break;
            commands[count][k] = (uint32_t)word;
        }
        if (k == 0)
            break;
        if (k != HALFPOINT_CMD_WORDS || count == MAX_COMMANDS - 1) {
            fprintf(stderr, "drive: %s: command %u: eight hex words per command, at most %d\n",
                    argv[1], count, MAX_COMMANDS - 1);
            fclose(in);
            return 2;
        }
        count++;
    }
    fclose(in);
    code = halfpoint_run((const uint32_t (*)[HALFPOINT_CMD_WORDS])commands, count);
    fprintf(stderr, "error code %d\n", code);
    printf("Q\n");
    return code < 0 ? 1 : 0;
}
#endif
