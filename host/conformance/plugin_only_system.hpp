// The cloth's system table with every callback, and every function of the host extensions
// (clothlab/ext/), routed through a pause of the allocation counter: only the plugin's own
// code is measured, not the host's force evaluation or solver kernels.
//
// The calls that may allocate on the host's side are for `prepare` only (plugin.h, jacobian.h):
// once the check calls close_prepare(), alloc_vector, reserve_rkn and the jacobian's reserve
// are refused, and so is any Jacobian, definite-Jacobian or cg-step call when the jacobian's
// reserve was not made in prepare (the host would allocate lazily in step). The first refusal
// is kept for the check's reason.
//
// An interposer owns the context its table hands out, so it can pass on only extensions
// whose tables it knows: a forwarded table's functions would receive this wrapper's
// context instead of the host's. Unknown ids are still asked of the host first, and so
// are known ones: an extension the host lacks stays NULL, an unknown one comes back NULL
// (never a table that would be called with the wrong context).
#pragma once

#include <clothlab/ext/attachment_targets.h>
#include <clothlab/ext/cg_step.h>
#include <clothlab/ext/contacts.h>
#include <clothlab/ext/definite_jacobian.h>
#include <clothlab/ext/external_forces.h>
#include <clothlab/ext/grid.h>
#include <clothlab/ext/jacobian.h>
#include <clothlab/ext/reductions.h>
#include <clothlab/ext/threads.h>
#include <clothlab/ext/topology.h>
#include <clothlab/plugin.h>

#include <span>
#include <string>

#include "allocation_counter.hpp"

namespace clothlab::conformance {

class PluginOnlySystem {
 public:
  explicit PluginOnlySystem(const clothlab_system& host);
  PluginOnlySystem(const PluginOnlySystem&) = delete;
  PluginOnlySystem& operator=(const PluginOnlySystem&) = delete;

  const clothlab_system& system() const { return system_; }

  // The host extensions it does not pass on (clothlab/core/extension_registry.hpp): none, so
  // the no-allocation check measures every path of the plugin's.
  static constexpr std::span<const char* const> kDeclinedExtensions{};

  // Prepare is over: from now on the prepare-only calls are refused.
  void close_prepare() { prepare_closed_ = true; }
  // "jacobian reserve called after prepare", ...: the first refused call, "" if none.
  const std::string& misuse() const { return misuse_; }

 private:
  // Refuses the call (returns false) and keeps its description when prepare is over.
  bool allowed_in_step(const char* call) const;
  // Refuses a call that needs the jacobian's reserve from prepare when there was none.
  bool jacobian_ready(const char* call) const;
  static clothlab_status reserve_jacobian(void* self);

  // Calls the host table's entry with the host's context while the counter is paused.
  template <class Table, auto Entry>
  struct Forward;
  template <class Table, class Result, class... Args, Result (*Table::*Entry)(void*, Args...)>
  struct Forward<Table, Entry> {
    static Result call(void* self, Args... args) {
      const allocations::Pause pause;
      const auto& wrapper = *static_cast<const PluginOnlySystem*>(self);
      const Table& table = *static_cast<const Table*>(wrapper.host_table<Table>());
      return (table.*Entry)(wrapper.host_.context, args...);
    }
  };
  // As Forward, for the tables whose calls need the jacobian's reserve made in prepare.
  template <class Table, auto Entry>
  struct AfterReserve;
  template <class Table, class... Args, clothlab_status (*Table::*Entry)(void*, Args...)>
  struct AfterReserve<Table, Entry> {
    static clothlab_status call(void* self, Args... args) {
      const allocations::Pause pause;
      const auto& wrapper = *static_cast<const PluginOnlySystem*>(self);
      if (!wrapper.jacobian_ready(extension_id<Table>())) return CLOTHLAB_ERROR_INVALID_ARGUMENT;
      return Forward<Table, Entry>::call(self, args...);
    }
  };

  template <class Table>
  const void* host_table() const;
  template <class Table>
  static const char* extension_id();
  static const void* get_extension(void* self, const char* id);

  const clothlab_system& host_;
  clothlab_system system_;
  const void* host_topology_ = nullptr;
  const void* host_jacobian_ = nullptr;
  const void* host_definite_jacobian_ = nullptr;
  const void* host_definite_jacobian_2_ = nullptr;
  const void* host_cg_step_ = nullptr;
  const void* host_reductions_ = nullptr;
  const void* host_external_forces_ = nullptr;
  const void* host_external_forces_2_ = nullptr;
  const void* host_threads_ = nullptr;
  const void* host_grid_ = nullptr;
  const void* host_contacts_ = nullptr;
  const void* host_attachment_targets_ = nullptr;
  bool prepare_closed_ = false;
  bool jacobian_reserved_in_prepare_ = false;
  mutable std::string misuse_;
};

}  // namespace clothlab::conformance
