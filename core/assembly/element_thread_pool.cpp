#include "core/assembly/element_thread_pool.h"

#include <algorithm>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace ff::assembly {

namespace {

thread_local bool inside_a_chunk = false;

// Every field below `state` is read and written under it only: the pool has no lock-free path,
// so ThreadSanitizer can follow each hand-over.
class ChunkPool {
 public:
  ~ChunkPool() {
    {
      std::lock_guard<std::mutex> lock(state_);
      quit_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : workers_) t.join();
  }

  void run(int chunks, const std::function<void(int)>& body) {
    std::lock_guard<std::mutex> one_loop(loop_);
    std::unique_lock<std::mutex> lock(state_);
    while (static_cast<int>(workers_.size()) < chunks - 1) workers_.emplace_back([this, g = generation_] { work(g); });
    body_ = &body;
    chunks_ = chunks;
    next_ = 0;
    unfinished_ = chunks;
    error_ = nullptr;
    ++generation_;
    lock.unlock();
    wake_.notify_all();
    lock.lock();
    run_claimed_chunks(lock);
    finished_.wait(lock, [this] { return unfinished_ == 0; });
    body_ = nullptr;
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  }

 private:
  // takes chunks of the current loop until none is left; called and returns with `lock` held
  void run_claimed_chunks(std::unique_lock<std::mutex>& lock) {
    while (next_ < chunks_) {
      const int c = next_++;
      const std::function<void(int)>& body = *body_;
      lock.unlock();
      std::exception_ptr failed;
      inside_a_chunk = true;
      try {
        body(c);
      } catch (...) {
        failed = std::current_exception();
      }
      inside_a_chunk = false;
      lock.lock();
      if (failed && !error_) error_ = failed;
      if (--unfinished_ == 0) finished_.notify_all();
    }
  }

  // `seen`: the loop generation when the thread was made, so that it joins the loop that made it
  void work(std::uint64_t seen) {
    std::unique_lock<std::mutex> lock(state_);
    for (;;) {
      wake_.wait(lock, [&] { return quit_ || generation_ != seen; });
      if (quit_) return;
      seen = generation_;
      run_claimed_chunks(lock);
    }
  }

  std::mutex loop_;   // one loop at a time
  std::mutex state_;  // everything below
  std::condition_variable wake_, finished_;
  std::vector<std::thread> workers_;
  const std::function<void(int)>* body_ = nullptr;
  int chunks_ = 0, next_ = 0, unfinished_ = 0;
  std::uint64_t generation_ = 0;
  std::exception_ptr error_;
  bool quit_ = false;
};

}  // namespace

void run_chunks_on_std_threads(int chunks, const std::function<void(int)>& body) {
  if (chunks <= 0) return;
  if (chunks == 1 || inside_a_chunk) {
    for (int c = 0; c < chunks; ++c) body(c);
    return;
  }
  static ChunkPool pool;
  pool.run(chunks, body);
}

}  // namespace ff::assembly
