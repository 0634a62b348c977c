// Faulty: evaluates the acceleration in its own worker thread (started in create), into a
// std::vector made there in every step. The calling thread never allocates, so a counter of
// the caller's allocations alone passes it; robustness.no-alloc counts every thread's.
#include <algorithm>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

#include "symplectic_euler.hpp"

struct AllocatesInWorkerThread : clothlab::faulty::SymplecticEulerBase {
  static constexpr const char* id = "allocates-in-worker-thread";
  static constexpr const char* name = "Integrator that allocates in its worker thread";
  static constexpr const char* description =
      "faulty: a std::vector per step in a thread of its own";

  explicit AllocatesInWorkerThread(const clothlab::sdk::Params& params)
      : SymplecticEulerBase(params), worker_([this] { serve(); }) {}

  ~AllocatesInWorkerThread() {
    {
      const std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    worker_.join();
  }

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    struct Evaluation {
      clothlab::sdk::System<Real>* system;
      double t;
      Real* a;
      static void run(void* context) {
        const Evaluation& job = *static_cast<Evaluation*>(context);
        std::vector<Real> scratch(3 * job.system->stride());
        job.system->acceleration(job.t, job.system->x(), job.system->v(), scratch.data());
        std::copy(scratch.begin(), scratch.end(), job.a);
      }
    } job{&system, t, static_cast<Real*>(acceleration_)};
    run_in_worker(&Evaluation::run, &job);
    system.axpy(system.v(), dt, job.a);
    system.axpy(system.x(), dt, system.v());
  }

 private:
  // Hands one job to the worker and waits for it: no allocation in the calling thread.
  void run_in_worker(void (*job)(void*), void* context) {
    std::unique_lock lock(mutex_);
    job_ = job;
    context_ = context;
    wake_.notify_all();
    done_.wait(lock, [this] { return job_ == nullptr; });
  }

  void serve() {
    std::unique_lock lock(mutex_);
    while (true) {
      wake_.wait(lock, [this] { return stopping_ || job_ != nullptr; });
      if (stopping_) return;
      job_(context_);
      job_ = nullptr;
      done_.notify_all();
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_, done_;
  void (*job_)(void*) = nullptr;
  void* context_ = nullptr;
  bool stopping_ = false;
  std::thread worker_;  // last: started once every member it uses exists
};

CLOTHLAB_PLUGIN_ENTRY("faulty-allocates-in-worker-thread", "0.0.1",
                      clothlab::sdk::integrators<AllocatesInWorkerThread>,
                      clothlab::sdk::scenarios<>)
