// LD_PRELOAD helper of bench/jit_profile.sh: copies every executable anonymous mapping (llvmpipe's JIT code)
// into JIT_DUMP_DIR before it is unmapped and at exit, as <start>_<length>.bin, so that the callgrind counts
// of code without an object file can be matched with its disassembly. Single-threaded use only (the shader
// JIT runs on the GL thread); a development tool, not part of ropecast.
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/mman.h>

enum { kMaxRegions = 4096 };
struct Region {
  char* start;
  size_t length;
  int live;
};
static struct Region regions[kMaxRegions];
static int regionCount;

static void remember(void* start, size_t length) {
  if (regionCount < kMaxRegions) regions[regionCount++] = (struct Region){start, length, 1};
}

static void dump(struct Region* r) {
  const char* dir = getenv("JIT_DUMP_DIR");
  if (!dir) return;
  char name[4096];
  snprintf(name, sizeof name, "%s/%lx_%zx.bin", dir, (unsigned long)r->start, r->length);
  FILE* f = fopen(name, "wb");
  if (f) {
    fwrite(r->start, 1, r->length, f);
    fclose(f);
  }
  r->live = 0;
}

void* mmap(void* addr, size_t length, int prot, int flags, int fd, off_t offset) {
  static void* (*real)(void*, size_t, int, int, int, off_t);
  if (!real) real = dlsym(RTLD_NEXT, "mmap");
  void* p = real(addr, length, prot, flags, fd, offset);
  if (p != MAP_FAILED && (prot & PROT_EXEC) && fd < 0) remember(p, length);
  return p;
}

void* mmap64(void* addr, size_t length, int prot, int flags, int fd, off_t offset) {
  return mmap(addr, length, prot, flags, fd, offset);
}

int mprotect(void* addr, size_t length, int prot) {
  static int (*real)(void*, size_t, int);
  if (!real) real = dlsym(RTLD_NEXT, "mprotect");
  int rc = real(addr, length, prot);
  if (rc == 0 && (prot & PROT_EXEC)) remember(addr, length);
  return rc;
}

int munmap(void* addr, size_t length) {
  static int (*real)(void*, size_t);
  if (!real) real = dlsym(RTLD_NEXT, "munmap");
  for (int i = 0; i < regionCount; ++i)
    if (regions[i].live && regions[i].start >= (char*)addr && regions[i].start < (char*)addr + length)
      dump(&regions[i]);
  return real(addr, length);
}

__attribute__((destructor)) static void dumpLiveRegions(void) {
  for (int i = 0; i < regionCount; ++i)
    if (regions[i].live) dump(&regions[i]);
}
