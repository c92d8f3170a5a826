/* A stand-in for OpenHaptics' libHD.so, built by the tests: it implements the HDAPI
 * calls haptic-loop uses, runs a 1 kHz "servo" thread like the real scheduler, serves pen
 * positions (a 20 mm circle at 0.5 Hz; button 1 down from frame 300), records the calls,
 * and can inject a device error. Not OpenHaptics code: written from the API's contract.
 *
 * The call record is written at hdDisableDevice to calls.log beside the library itself.
 * Environment: SAIHO_STANDIN_ERROR_AT (frame from which hdGetError reports 0x0300),
 * SAIHO_STANDIN_CALIBRATION (status hdCheckCalibration returns, default 0x5000),
 * SAIHO_STANDIN_GLITCH_AT (frame from which the position reads 5 m away, as a glitching
 * encoder might, or NaN from twice that frame on). */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <libgen.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

typedef unsigned int HHD;
typedef unsigned int (*cb_t)(void *);
typedef struct { unsigned int errorCode; int internalErrorCode; HHD hHD; } HDErrorInfo;

static cb_t g_cb;
static void *g_data;
static volatile int g_running, g_in_frame, g_enabled_force;
static pthread_t g_thread;
static long g_frames, g_forces, g_bad_forces, g_frame_errors, g_error_at = -1, g_glitch_at = -1;
static double g_max_force;
static char g_log[8192];
static unsigned int g_error;

static void rec(const char *s) { strncat(g_log, s, sizeof g_log - strlen(g_log) - 1); strncat(g_log, "\n", sizeof g_log - strlen(g_log) - 1); }

HHD hdInitDevice(const char *name) {
    const char *e = getenv("SAIHO_STANDIN_ERROR_AT");
    g_error_at = e ? atol(e) : -1;
    const char *g = getenv("SAIHO_STANDIN_GLITCH_AT");
    g_glitch_at = g ? atol(g) : -1;
    g_log[0] = 0;
    rec(name ? "hdInitDevice named" : "hdInitDevice default");
    return 1;
}
void hdEnable(unsigned int cap) { char b[64]; snprintf(b, sizeof b, "hdEnable %#x", cap); rec(b); if (cap == 0x4000) g_enabled_force = 1; }
unsigned int hdCheckCalibration(void) { const char *e = getenv("SAIHO_STANDIN_CALIBRATION"); rec("hdCheckCalibration"); return e ? (unsigned int)strtoul(e, 0, 0) : 0x5000; }
void hdUpdateCalibration(unsigned int style) { char b[64]; snprintf(b, sizeof b, "hdUpdateCalibration %#x", style); rec(b); }
HDErrorInfo hdGetError(void) { HDErrorInfo i = { g_error, 0, 1 }; return i; }
void hdBeginFrame(HHD h) { (void)h; if (g_in_frame) g_frame_errors++; g_in_frame = 1; }
void hdEndFrame(HHD h) {
    (void)h; if (!g_in_frame) g_frame_errors++; g_in_frame = 0; g_frames++;
    if (g_error_at >= 0 && g_frames >= g_error_at) g_error = 0x0300;
}
static double now_s(void) { struct timespec t; clock_gettime(CLOCK_MONOTONIC, &t); return t.tv_sec + t.tv_nsec * 1e-9; }
void hdGetDoublev(unsigned int p, double *v) {
    double t = g_frames * 0.001, w = 2 * M_PI * 0.5;
    if (!g_in_frame) g_frame_errors++;
    if (p == 0x2050) { v[0] = 20 * cos(w * t); v[1] = 20 * sin(w * t); v[2] = 0; }
    else if (p == 0x2051) { v[0] = -20 * w * sin(w * t); v[1] = 20 * w * cos(w * t); v[2] = 0; }
    else { v[0] = v[1] = v[2] = 0; }
    if (p == 0x2050 && g_glitch_at >= 0 && g_frames >= g_glitch_at)
        v[2] = g_frames >= 2 * g_glitch_at ? NAN : 5000.0;
}
void hdGetIntegerv(unsigned int p, int *v) { if (!g_in_frame) g_frame_errors++; *v = (p == 0x2000 && g_frames >= 300) ? 1 : 0; }
void hdSetDoublev(unsigned int p, const double *v) {
    if (!g_in_frame) g_frame_errors++;
    if (p != 0x2700) return;
    g_forces++;
    double m = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!isfinite(m)) g_bad_forces++; else if (m > g_max_force) g_max_force = m;
}
static void *servo(void *arg) {
    (void)arg;
    double next = now_s();
    while (g_running) {
        next += 0.001;
        double d = next - now_s();
        if (d > 0) { struct timespec ts = { 0, (long)(d * 1e9) }; nanosleep(&ts, 0); }
        if (g_cb && g_cb(g_data) == 0) g_cb = 0;
    }
    return 0;
}
unsigned long hdScheduleAsynchronous(cb_t cb, void *data, unsigned short prio) { char b[64]; snprintf(b, sizeof b, "hdScheduleAsynchronous %u", prio); rec(b); g_cb = cb; g_data = data; return 7; }
void hdStartScheduler(void) { rec("hdStartScheduler"); g_running = 1; pthread_create(&g_thread, 0, servo, 0); }
void hdStopScheduler(void) { rec("hdStopScheduler"); if (g_running) { g_running = 0; pthread_join(g_thread, 0); } }
void hdUnschedule(unsigned long h) { char b[64]; snprintf(b, sizeof b, "hdUnschedule %lu", h); rec(b); g_cb = 0; }
void hdDisableDevice(HHD h) {
    char b[256];
    (void)h;
    rec("hdDisableDevice");
    snprintf(b, sizeof b, "frames %ld forces %ld bad_forces %ld max_force %.4f frame_errors %ld force_enabled %d",
             g_frames, g_forces, g_bad_forces, g_max_force, g_frame_errors, g_enabled_force);
    rec(b);
    Dl_info info;
    if (dladdr((void *)hdDisableDevice, &info) && info.dli_fname) {
        char dir[4096], path[4200];
        strncpy(dir, info.dli_fname, sizeof dir - 1);
        dir[sizeof dir - 1] = 0;
        snprintf(path, sizeof path, "%s/calls.log", dirname(dir));
        FILE *f = fopen(path, "w");
        if (f) { fputs(g_log, f); fclose(f); }
    }
}
