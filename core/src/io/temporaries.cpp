#include "redpost/io/temporaries.hpp"

#include <fcntl.h>
#include <sys/random.h>
#include <time.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>

#include "redpost/io/error.hpp"

namespace redpost {
namespace fs = std::filesystem;

namespace {

// One slot of the clean-up list. Slots are never freed: a signal handler may walk the list at
// any moment without a lock, so a slot only changes hands through `state`, and its buffer is
// written only while the slot is `writing` (the handler skips those). Threads that register and
// forget take `g_mutex`, which orders their reads and writes of the paths.
struct Slot {
  enum : int { free_slot, writing, live };
  std::atomic<int> state{free_slot};
  char* path = nullptr;
  size_t capacity = 0;
  Slot* next = nullptr;
};

std::atomic<Slot*> g_slots{nullptr};
std::mutex g_mutex;

// FileSection's count of sections under way, and whether a stop was requested. Lock-free, so
// that a signal handler may read and write them.
std::atomic<int> g_sections{0};
std::atomic<bool> g_stopping{false};
static_assert(std::atomic<int>::is_always_lock_free && std::atomic<bool>::is_always_lock_free);

// Holds SIGTERM, SIGINT and SIGHUP back in this thread; `old` gets the mask to put back.
void hold_stop_signals(sigset_t* old) {
  sigset_t stop;
  sigemptyset(&stop);
  sigaddset(&stop, SIGTERM);
  sigaddset(&stop, SIGINT);
  sigaddset(&stop, SIGHUP);
  ::pthread_sigmask(SIG_BLOCK, &stop, old);
}

// The stop signals held back for its lifetime: around g_mutex too, so that a handler never runs
// on a thread that holds it while it waits for a section that needs it.
class StopSignalsHeld {
 public:
  StopSignalsHeld() { hold_stop_signals(&old_); }
  ~StopSignalsHeld() { ::pthread_sigmask(SIG_SETMASK, &old_, nullptr); }
  StopSignalsHeld(const StopSignalsHeld&) = delete;
  StopSignalsHeld& operator=(const StopSignalsHeld&) = delete;

 private:
  sigset_t old_;
};

void sleep_ms(long ms) {
  timespec t{ms / 1000, (ms % 1000) * 1000000L};
  while (::nanosleep(&t, &t) != 0 && errno == EINTR) {
  }
}

// At exit (or when the library is unloaded): the temporaries go, and so does the list, so that
// nothing the registry holds is left for a leak checker. A signal after this finds no list.
void remove_at_exit() {
  remove_all_temporaries();
  Slot* s = g_slots.exchange(nullptr);
  while (s) {
    Slot* next = s->next;
    delete[] s->path;
    delete s;
    s = next;
  }
}

// A free slot, or a new one at the head of the list; called with g_mutex held.
Slot* claim_slot() {
  for (Slot* s = g_slots.load(std::memory_order_acquire); s; s = s->next) {
    if (s->state.load(std::memory_order_relaxed) == Slot::free_slot) {
      s->state.store(Slot::writing, std::memory_order_relaxed);
      return s;
    }
  }
  auto* s = new Slot;
  s->state.store(Slot::writing, std::memory_order_relaxed);
  s->next = g_slots.load(std::memory_order_relaxed);
  g_slots.store(s, std::memory_order_release);
  return s;
}

// Eight letters from the kernel's random source (a counter mixed with the pid where it has none),
// enough that a clash, which O_EXCL catches anyway, is rare.
std::string random_tag() {
  static constexpr char kLetters[] = "abcdefghijklmnopqrstuvwxyz0123456789";
  unsigned char bytes[8];
  if (::getrandom(bytes, sizeof bytes, GRND_NONBLOCK) != static_cast<ssize_t>(sizeof bytes)) {
    static std::atomic<unsigned> counter{0};
    const unsigned v = counter.fetch_add(1) * 2654435761u ^ static_cast<unsigned>(::getpid());
    for (size_t i = 0; i < sizeof bytes; ++i)
      bytes[i] = static_cast<unsigned char>(v >> (i * 4));
  }
  std::string tag(sizeof bytes, 'x');
  for (size_t i = 0; i < sizeof bytes; ++i)
    tag[i] = kLetters[bytes[i] % (sizeof kLetters - 1)];
  return tag;
}

// Opens a new file beside `final_path`; returns its descriptor and sets `path`.
int open_unique(const std::string& final_path, const char* suffix, std::string& path) {
  const fs::path p(final_path);
  for (int attempt = 0; attempt < 100; ++attempt) {
    path = (p.parent_path() / ("." + p.filename().string() + "." + random_tag() + suffix)).string();
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd >= 0)
      return fd;
    if (errno != EEXIST) {
      throw Error(ErrorCode::io,
                  std::string("cannot create a file beside it: ") + std::strerror(errno) +
                      "; check that the folder exists and is writable",
                  SourceLocation{final_path, 0, 0});
    }
  }
  throw Error(ErrorCode::io, "cannot create a temporary file beside it: 100 names were all taken",
              SourceLocation{final_path, 0, 0});
}

}  // namespace

void register_temporary(const std::string& path) {
  static std::once_flag once;
  std::call_once(once, [] { std::atexit(remove_at_exit); });
  const StopSignalsHeld held;
  const std::lock_guard<std::mutex> lock(g_mutex);
  Slot* s = claim_slot();
  if (s->capacity < path.size() + 1) {
    delete[] s->path;  // the slot is `writing`: no handler reads it
    s->capacity = path.size() + 1;
    s->path = new char[s->capacity];
  }
  std::memcpy(s->path, path.c_str(), path.size() + 1);
  s->state.store(Slot::live, std::memory_order_release);
}

void forget_temporary(const std::string& path) noexcept {
  const StopSignalsHeld held;
  const std::lock_guard<std::mutex> lock(g_mutex);
  for (Slot* s = g_slots.load(std::memory_order_acquire); s; s = s->next) {
    if (s->state.load(std::memory_order_relaxed) == Slot::live && path == s->path) {
      s->state.store(Slot::free_slot, std::memory_order_release);
      return;
    }
  }
}

void remove_temporary(const std::string& path) noexcept {
  ::unlink(path.c_str());
  forget_temporary(path);
}

void remove_all_temporaries() noexcept {
  const int saved_errno = errno;
  for (Slot* s = g_slots.load(std::memory_order_acquire); s; s = s->next) {
    if (s->state.load(std::memory_order_acquire) == Slot::live)
      ::unlink(s->path);
  }
  errno = saved_errno;
}

FileSection::FileSection() {
  hold_stop_signals(&old_);
  g_sections.fetch_add(1);
  // Counted first, then the flag read (both sequentially consistent): a handler that set the
  // flag before this read waits for the count; one that sets it after finds the count.
  while (g_stopping.load()) {
    g_sections.fetch_sub(1);
    sleep_ms(1000);  // the handler ends the process
    g_sections.fetch_add(1);
  }
}

FileSection::~FileSection() {
  g_sections.fetch_sub(1);
  ::pthread_sigmask(SIG_SETMASK, &old_, nullptr);
}

void stop_and_remove_temporaries() noexcept {
  const int saved_errno = errno;
  g_stopping.store(true);
  for (int waited = 0; g_sections.load() > 0 && waited < 5000; ++waited)
    sleep_ms(1);
  errno = saved_errno;
  remove_all_temporaries();
}

std::string create_unique_beside(const std::string& final_path, const char* suffix) {
  std::string path;
  ::close(open_unique(final_path, suffix, path));
  return path;
}

Temporary create_temporary(const std::string& final_path) {
  Temporary t;
  int fd = -1;
  {
    const FileSection section;  // made and registered, or not made
    fd = open_unique(final_path, ".part~", t.path);
    register_temporary(t.path);
  }
  t.file = ::fdopen(fd, "wb");
  if (!t.file) {
    const int err = errno;
    ::close(fd);
    remove_temporary(t.path);
    throw Error(ErrorCode::io, std::string("cannot open the temporary file: ") + std::strerror(err),
                SourceLocation{final_path, 0, 0});
  }
  std::setvbuf(t.file, nullptr, _IOFBF, 1 << 16);
  return t;
}

}  // namespace redpost
