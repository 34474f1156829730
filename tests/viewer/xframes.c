/* xframes: how often a region of an X display really changes on screen (frames a
 * window shows, e.g. while xdotool drags in it under Xvfb). Samples the region every
 * PERIOD_MS for SECONDS through MIT-SHM and prints one line per change, then
 *   "changes C samples N max_gap_ms G"
 * where G is the longest time the region stood still. The first line,
 *   "start E", gives the wall-clock time (seconds since the epoch) of time 0.
 * Usage: DISPLAY=:N xframes X Y W H PERIOD_MS SECONDS */
#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <X11/extensions/XShm.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/ipc.h>
#include <sys/shm.h>
#include <time.h>
#include <unistd.h>

static double seconds(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

int main(int argc, char** argv) {
    if (argc != 7) {
        fprintf(stderr, "usage: xframes X Y W H PERIOD_MS SECONDS\n");
        return 2;
    }
    int x = atoi(argv[1]), y = atoi(argv[2]), w = atoi(argv[3]), h = atoi(argv[4]);
    double period = atof(argv[5]) / 1000, duration = atof(argv[6]);
    if (w < 1 || h < 1 || period <= 0 || duration <= 0) {
        fprintf(stderr, "xframes: bad region or timing\n");
        return 2;
    }
    Display* dpy = XOpenDisplay(NULL);
    if (!dpy) {
        fprintf(stderr, "xframes: cannot open the display\n");
        return 1;
    }
    int screen = DefaultScreen(dpy);
    XShmSegmentInfo shm;
    XImage* img = XShmCreateImage(dpy, DefaultVisual(dpy, screen), (unsigned)DefaultDepth(dpy, screen), ZPixmap, NULL,
                                  &shm, (unsigned)w, (unsigned)h);
    if (!img) {
        fprintf(stderr, "xframes: no shared-memory image\n");
        return 1;
    }
    shm.shmid = shmget(IPC_PRIVATE, (size_t)img->bytes_per_line * (size_t)img->height, IPC_CREAT | 0600);
    shm.shmaddr = img->data = shmat(shm.shmid, NULL, 0);
    shm.readOnly = False;
    XShmAttach(dpy, &shm);
    shmctl(shm.shmid, IPC_RMID, NULL); /* freed when detached, even if we are killed */
    double t0 = seconds(), last = t0, max_gap = 0;
    struct timespec wall;
    clock_gettime(CLOCK_REALTIME, &wall);
    printf("start %.6f\n", (double)wall.tv_sec + (double)wall.tv_nsec * 1e-9);
    fflush(stdout); /* a script waits for this line before it starts what is watched */
    uint64_t prev = 0;
    int changes = 0, samples = 0;
    while (seconds() - t0 < duration) {
        XShmGetImage(dpy, DefaultRootWindow(dpy), img, x, y, AllPlanes);
        const unsigned char* b = (const unsigned char*)img->data;
        size_t n = (size_t)img->bytes_per_line * (size_t)img->height;
        uint64_t hash = 14695981039346656037ULL; /* FNV-1a over every 5th byte */
        for (size_t i = 0; i < n; i += 5) hash = (hash ^ b[i]) * 1099511628211ULL;
        double t = seconds();
        if (samples > 0 && hash != prev) {
            ++changes;
            if (t - last > max_gap) max_gap = t - last;
            printf("%.3f change (gap %.0f ms)\n", t - t0, (t - last) * 1000);
            last = t;
        }
        if (samples == 0) last = t;
        prev = hash;
        ++samples;
        double wait = t0 + samples * period - seconds();
        if (wait > 0) usleep((useconds_t)(wait * 1e6));
    }
    double end = seconds();
    if (end - last > max_gap) max_gap = end - last;
    printf("changes %d samples %d max_gap_ms %.0f\n", changes, samples, max_gap * 1000);
    XShmDetach(dpy, &shm);
    shmdt(shm.shmaddr);
    XCloseDisplay(dpy);
    return 0;
}
