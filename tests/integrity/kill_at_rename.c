/* Fault injection for tests/integrity/test_rename_window.sh, loaded with LD_PRELOAD: the process
 * kills itself with SIGKILL just before its N-th call of rename(2), N from the environment
 * variable REDPOST_KILL_AT_RENAME (1-based; unset or 0: never). This lands a kill exactly in the
 * window between two renames of a program's files, which random delays almost never hit. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

int rename(const char* from, const char* to) {
  static int calls = 0;
  static int (*real_rename)(const char*, const char*) = NULL;
  if (real_rename == NULL)
    real_rename = (int (*)(const char*, const char*))dlsym(RTLD_NEXT, "rename");
  const char* at = getenv("REDPOST_KILL_AT_RENAME");
  if (at != NULL && ++calls == atoi(at))
    kill(getpid(), SIGKILL);
  return real_rename(from, to);
}
