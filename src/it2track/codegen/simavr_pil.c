/* Processor in the loop: the host side of it2track's PIL firmware, over libsimavr.
 *
 * Compiled at run time with the host's gcc into a shared library (it2track.codegen.pil) and
 * called through ctypes, which releases the GIL during each call, so several simulated MCUs
 * can run on several threads.
 *
 * One pil_mcu is one simulated ATmega328P with the PIL firmware loaded once (pil_open). The
 * firmware keeps its exchange block at a fixed SRAM address (found with avr-nm) and writes
 * GPIOR0 when it is ready for the next inputs, i.e. after it has stored the outputs of the
 * previous call. pil_step, for each of n inputs in turn: copies the input bytes into the
 * exchange block, runs the MCU until its next write to GPIOR0, and copies the output bytes
 * back. The simulated MCU does not run between two calls: the host is the control period's
 * trigger. The generated controller keeps no state between calls, so one MCU can serve the
 * runs of a batch in turn. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "sim_avr.h"
#include "sim_elf.h"
#include "sim_io.h"

#define PIL_OK 0
#define PIL_ERR_ELF 1
#define PIL_ERR_MCU 2
#define PIL_ERR_STOPPED 3
#define PIL_ERR_TIMEOUT 4
#define PIL_ERR_RANGE 5

typedef struct pil_mcu {
    avr_t *avr;
    volatile int ready; /* set by the GPIOR0 write callback */
    uint16_t block;     /* SRAM address of the exchange block */
} pil_mcu;

static void quiet(avr_t *avr, const int level, const char *format, va_list ap)
{
    (void)avr;
    (void)level;
    (void)format;
    (void)ap;
}

static void on_ready(avr_t *avr, avr_io_addr_t addr, uint8_t v, void *param)
{
    (void)avr;
    (void)addr;
    (void)v;
    ((pil_mcu *)param)->ready = 1;
}

/* Run until the firmware signals; 0, or an error if it stops or exceeds max_cycles. */
static int run_until_ready(pil_mcu *m, uint64_t max_cycles)
{
    avr_t *avr = m->avr;
    avr_cycle_count_t start = avr->cycle;
    m->ready = 0;
    while (!m->ready) {
        int state = avr_run(avr);
        if (state == cpu_Done || state == cpu_Crashed) {
            return PIL_ERR_STOPPED;
        }
        if (avr->cycle - start > max_cycles) {
            return PIL_ERR_TIMEOUT;
        }
    }
    return PIL_OK;
}

int pil_open(const char *elf, const char *mcu, uint32_t frequency, uint16_t ready_addr,
             uint16_t block, uint64_t max_cycles, pil_mcu **out);
int pil_step(pil_mcu *m, long n, const uint8_t *in, long in_bytes, long in_offset,
             uint8_t *out, long out_bytes, long out_offset, uint64_t max_cycles);
void pil_close(pil_mcu *m);
uint64_t pil_cycle(const pil_mcu *m);

int pil_open(const char *elf, const char *mcu, uint32_t frequency, uint16_t ready_addr,
             uint16_t block, uint64_t max_cycles, pil_mcu **out)
{
    /* elf_firmware_t's size depends on how libsimavr was configured (ELF_SYMBOLS): room to
     * spare, zeroed. */
    union {
        elf_firmware_t f;
        unsigned char pad[sizeof(elf_firmware_t) + 4096];
    } fw;
    pil_mcu *m;
    int status;
    *out = NULL;
    avr_global_logger_set(quiet);
    memset(&fw, 0, sizeof fw);
    if (elf_read_firmware(elf, &fw.f) != 0) {
        return PIL_ERR_ELF;
    }
    m = calloc(1, sizeof *m);
    if (m == NULL) {
        return PIL_ERR_MCU;
    }
    m->avr = avr_make_mcu_by_name(mcu);
    if (m->avr == NULL) {
        free(m);
        return PIL_ERR_MCU;
    }
    avr_init(m->avr);
    m->avr->log = LOG_NONE;
    avr_load_firmware(m->avr, &fw.f);
    free(fw.f.flash);
    m->avr->frequency = frequency;
    m->block = block;
    if ((uint32_t)block + 64u > (uint32_t)m->avr->ramend + 1u || ready_addr < 0x20u
        || ready_addr >= 0x100u) {
        pil_close(m);
        return PIL_ERR_RANGE;
    }
    avr_register_io_write(m->avr, ready_addr, on_ready, m);
    status = run_until_ready(m, max_cycles); /* start-up: the first "ready" */
    if (status != PIL_OK) {
        pil_close(m);
        return status;
    }
    *out = m;
    return PIL_OK;
}

int pil_step(pil_mcu *m, long n, const uint8_t *in, long in_bytes, long in_offset,
             uint8_t *out, long out_bytes, long out_offset, uint64_t max_cycles)
{
    uint8_t *data = m->avr->data + m->block;
    long j;
    for (j = 0; j < n; ++j) {
        int status;
        memcpy(data + in_offset, in + j * in_bytes, (size_t)in_bytes);
        status = run_until_ready(m, max_cycles);
        if (status != PIL_OK) {
            return status;
        }
        memcpy(out + j * out_bytes, data + out_offset, (size_t)out_bytes);
    }
    return PIL_OK;
}

uint64_t pil_cycle(const pil_mcu *m)
{
    return (uint64_t)m->avr->cycle;
}

void pil_close(pil_mcu *m)
{
    if (m == NULL) {
        return;
    }
    if (m->avr != NULL) {
        avr_terminate(m->avr);
        free(m->avr);
    }
    free(m);
}
