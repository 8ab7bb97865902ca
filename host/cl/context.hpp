#pragma once
// A device's context and in-order queue, its program cache and its memory accounting.
// Everything else (buffers, programs, kernels) is created through a Context and must not outlive it.
#include <CL/cl.h>

#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "cl/device.hpp"
#include "cl/handle.hpp"
#include "cl/program.hpp"

namespace clr::cl {

class Context {
 public:
  explicit Context(DeviceInfo device);
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
  ~Context();

  const DeviceInfo& device() const { return device_; }
  cl_context get() const { return context_.get(); }
  cl_command_queue queue() const { return queue_.get(); }
  // A second in-order queue for reads the main queue's later kernels need not wait for, so that a GPU's copy engine
  // runs them beside its compute (cl::PinnedDownload); made on first use. Its commands follow the main queue's by
  // events, and are left out of the device's busy time below (they overlap it).
  cl_command_queue transfer_queue() const;
  void finish() const;  // both queues

  // The program made of these kernel files (concatenated in order) built with these options; built once per
  // (files, options) and cached for the life of the context. Build failures throw with the build log.
  const Program& program(const std::vector<std::string>& files, const std::string& options = "");
  std::size_t programs_built() const { return programs_built_; }

  // Device-memory accounting of Buffers created on this context (docs/design.md §6: peak memory is reported).
  void on_alloc(std::uint64_t bytes);
  void on_free(std::uint64_t bytes) { bytes_in_use_ -= bytes; }
  std::uint64_t bytes_in_use() const { return bytes_in_use_; }
  std::uint64_t peak_bytes() const { return peak_bytes_; }
  void reset_peak() { peak_bytes_ = bytes_in_use_; }

  // The device's busy time (benchmarks: a step's device share beside its host stages). While recording, every
  // command this layer enqueues keeps its event, and take_device_seconds() waits for the queue and sums their
  // profiled durations: the in-order queue runs one command at a time, so the sum is the time the device worked,
  // its idle gaps (a host that cannot keep up) left out. Off by default: training keeps no events.
  void record_device_time(bool on) { recording_ = on; }
  // Where an enqueue puts its event: null when not recording.
  cl_event* event_slot() const;
  // The same for a call that enqueues several commands but returns one event (CLBlast: its last): a marker before
  // it opens the span, which that event closes.
  cl_event* span_slot() const;
  // Keeps an event the caller owns (retained here).
  void record(cl_event event) const;
  double take_device_seconds();
  // Seconds the host spent blocked until the device freed pinned memory for reuse (cl/async.hpp): a device behind the
  // host. Only accumulates; readers take differences.
  void add_wait(double seconds) const { waited_s_ += seconds; }
  double waited_seconds() const { return waited_s_; }

 private:
  DeviceInfo device_;
  ContextHandle context_;
  QueueHandle queue_;
  mutable QueueHandle transfer_;
  std::map<std::string, std::unique_ptr<Program>> programs_;
  std::size_t programs_built_ = 0;
  std::uint64_t bytes_in_use_ = 0;
  std::uint64_t peak_bytes_ = 0;
  struct Timed {
    cl_event opened = nullptr;  // a marker whose end opens the span; null: the command's own start does
    cl_event command = nullptr;
    void release() const {
      if (opened) clReleaseEvent(opened);
      if (command) clReleaseEvent(command);
    }
  };
  bool recording_ = false;
  mutable double waited_s_ = 0;
  mutable std::deque<Timed> timed_;  // a deque: a slot's address stays valid while later ones are added
};

}  // namespace clr::cl
