/* Counts folder listings for tests/integrity/test_check_scaling.sh, loaded with LD_PRELOAD: every
 * opendir(3) and fdopendir(3) of the process is counted, and the count is written at exit to the
 * file named by REDPOST_COUNT_LISTINGS. A check that lists its folder once per file is quadratic
 * in the number of files; the count shows it without timing anything. */
#define _GNU_SOURCE
#include <dirent.h>
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>

static long listings = 0;

DIR* opendir(const char* name) {
  static DIR* (*real_opendir)(const char*) = NULL;
  if (real_opendir == NULL)
    real_opendir = (DIR * (*)(const char*)) dlsym(RTLD_NEXT, "opendir");
  ++listings;
  return real_opendir(name);
}

DIR* fdopendir(int fd) {
  static DIR* (*real_fdopendir)(int) = NULL;
  if (real_fdopendir == NULL)
    real_fdopendir = (DIR * (*)(int)) dlsym(RTLD_NEXT, "fdopendir");
  ++listings;
  return real_fdopendir(fd);
}

__attribute__((destructor)) static void report(void) {
  const char* path = getenv("REDPOST_COUNT_LISTINGS");
  if (path == NULL)
    return;
  FILE* f = fopen(path, "w");
  if (f != NULL) {
    fprintf(f, "%ld\n", listings);
    fclose(f);
  }
}
