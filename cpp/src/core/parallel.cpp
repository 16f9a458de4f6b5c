#include "ifsforge/core/parallel.h"

#include "ifsforge/core/default_threads.h"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include "ifsforge/core/error.h"

namespace ifsforge {

namespace {
std::atomic<int> default_threads{0};

/// The stop flag of the parallel_jobs whose job runs on this thread (nested calls restore it).
thread_local const std::atomic<bool>* current_stop = nullptr;

struct StopScope {
  explicit StopScope(const std::atomic<bool>* stop) : saved(current_stop) { current_stop = stop; }
  ~StopScope() { current_stop = saved; }
  const std::atomic<bool>* saved;
};
}  // namespace

void set_default_threads(int threads) {
  if (threads < 0) throw InputError("threads must be >= 0 (0: all cores), got " + std::to_string(threads));
  default_threads = threads;
}

int resolve_threads(int requested) {
  if (requested > 0) return requested;
  if (const int preset = default_threads.load(); preset > 0) return preset;
  const unsigned hw = std::thread::hardware_concurrency();
  return hw == 0 ? 1 : static_cast<int>(hw);
}

bool stop_requested() { return current_stop && current_stop->load(std::memory_order_relaxed); }

namespace {

/// One parallel_jobs call's shared state. Helpers hold it by shared_ptr: one that wakes after
/// the call returned still reads valid counters (it finds no job left and touches nothing else).
struct Task {
  std::size_t jobs = 0;
  const std::function<void(std::size_t, int)>* job = nullptr;
  std::atomic<std::size_t> next{0}, done{0};
  std::atomic<bool> stop{false};
  std::atomic<int> active{0};  // helpers inside run(): the caller returns once none is
  std::exception_ptr failure;
  std::mutex mutex;
  std::condition_variable changed;

  void fail(std::exception_ptr e) {
    std::lock_guard<std::mutex> lock(mutex);
    if (!failure) failure = e;
    stop = true;
    changed.notify_all();
  }

  /// Claims and runs jobs until none is left or the work stops.
  void run(int worker) {
    const StopScope scope(&stop);
    for (;;) {
      if (stop.load()) return;
      const std::size_t index = next.fetch_add(1);
      if (index >= jobs) return;
      try {
        (*job)(index, worker);
      } catch (...) {
        fail(std::current_exception());
        return;
      }
      if (done.fetch_add(1) + 1 == jobs) {
        std::lock_guard<std::mutex> lock(mutex);
        changed.notify_all();
      }
    }
  }

  /// A helper's share: counted in `active` before it claims anything. The caller looks at
  /// `active` only after the last claim or the stop, so a helper it did not see claims nothing.
  void help(int worker) {
    active.fetch_add(1);
    run(worker);
    if (active.fetch_sub(1) == 1) {
      std::lock_guard<std::mutex> lock(mutex);
      changed.notify_all();
    }
  }
};

/// Threads kept between calls: a call wakes idle ones (starting more only when none is idle,
/// so nested calls never wait for a busy one) instead of starting and joining threads each
/// time, a cost per thread and per call that grew with the cores. Never destroyed: its threads
/// sleep until the process ends. A child process after fork() has none of them: it starts a
/// pool of its own.
class HelperPool {
 public:
  static HelperPool& instance() {
    static std::atomic<HelperPool*> current{nullptr};
    HelperPool* pool = current.load();
    if (pool && pool->pid_ == getpid()) return *pool;
    auto* fresh = new HelperPool();  // the parent's (copied, threadless) is left as it is
    if (current.compare_exchange_strong(pool, fresh)) return *fresh;
    delete fresh;
    return *pool;
  }

  /// Runs task.help(worker) for worker in [first, last) on idle or new threads; returns how
  /// many took it (fewer when the system refuses another thread: the caller's work goes on).
  int dispatch(const std::shared_ptr<Task>& task, int first, int last) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (int worker = first; worker < last; ++worker) {
      Helper* helper;
      if (!idle_.empty()) {
        helper = idle_.back();
        idle_.pop_back();
      } else {
        auto fresh = std::make_unique<Helper>();
        try {
          std::thread(&HelperPool::serve, this, fresh.get()).detach();
        } catch (const std::system_error&) {
          return worker - first;
        }
        helper = fresh.release();
      }
      helper->task = task;
      helper->worker = worker;
      helper->wake.notify_one();
    }
    return last - first;
  }

 private:
  struct Helper {
    std::condition_variable wake;
    std::shared_ptr<Task> task;  // set (under the pool's mutex) to hand it work
    int worker = 0;
  };

  void serve(Helper* helper) {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      helper->wake.wait(lock, [&] { return helper->task != nullptr; });
      std::shared_ptr<Task> task = std::move(helper->task);
      helper->task = nullptr;
      const int worker = helper->worker;
      lock.unlock();
      task->help(worker);
      task.reset();
      lock.lock();
      idle_.push_back(helper);
    }
  }

  const pid_t pid_ = getpid();
  std::mutex mutex_;
  std::vector<Helper*> idle_;
};

}  // namespace

void parallel_jobs(std::size_t jobs, int threads,
                   const std::function<void(std::size_t, int)>& job,
                   const ProgressCallback& progress) {
  threads = resolve_threads(threads);
  if (static_cast<std::size_t>(threads) > jobs) threads = static_cast<int>(jobs > 0 ? jobs : 1);
  auto task = std::make_shared<Task>();
  task->jobs = jobs;
  task->job = &job;

  // With a callback the calling thread does no job: it reports every 0.1 s and cancels, so a
  // single long job (the fern's densest address prefix at 6000^2 runs for half a minute) does
  // not hold Ctrl-C; jobs see the stop through stop_requested().
  bool supervise = static_cast<bool>(progress);
  if (threads > 1 || supervise) {
    // No helper at all for a supervising caller: it runs the jobs itself.
    if (HelperPool::instance().dispatch(task, supervise ? 0 : 1, threads) == 0 && supervise) {
      supervise = false;
    }
  }
  if (supervise) {
    // The predicate is checked before waiting: work that ended before this line costs no wait.
    auto over = [&] { return task->stop.load() || task->done.load() >= jobs; };
    std::unique_lock<std::mutex> lock(task->mutex);
    while (!task->changed.wait_for(lock, std::chrono::milliseconds(100), over)) {
      lock.unlock();
      // The callback may throw (a Python error): stop the workers before passing it on.
      std::exception_ptr stopped;
      try {
        if (!progress(static_cast<double>(task->done.load()) / static_cast<double>(jobs))) stopped = std::make_exception_ptr(Cancelled());
      } catch (...) {
        stopped = std::current_exception();
      }
      if (stopped) task->fail(stopped);
      lock.lock();
    }
  } else {
    task->run(0);
  }
  // Every job is claimed (or the work stopped): wait for the helpers still running one, not
  // for those that have yet to wake (they will find nothing left).
  {
    std::unique_lock<std::mutex> lock(task->mutex);
    task->changed.wait(lock, [&] { return task->active.load() == 0; });
  }
  if (task->failure) std::rethrow_exception(task->failure);
  if (progress && !progress(1.0)) throw Cancelled();
}

}  // namespace ifsforge
