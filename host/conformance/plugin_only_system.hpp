// The cloth's system table with every callback, and every function of the host extensions
// (clothlab/ext/), routed through a pause of the allocation counter: only the plugin's own
// code is measured, not the host's force evaluation or solver kernels.
//
// An interposer owns the context its table hands out, so it can pass on only extensions
// whose tables it knows: a forwarded table's functions would receive this wrapper's
// context instead of the host's. Unknown ids are still asked of the host first, and so
// are known ones: an extension the host lacks stays NULL, an unknown one comes back NULL
// (never a table that would be called with the wrong context).
#pragma once

#include <clothlab/ext/cg_step.h>
#include <clothlab/ext/definite_jacobian.h>
#include <clothlab/ext/external_forces.h>
#include <clothlab/ext/jacobian.h>
#include <clothlab/ext/reductions.h>
#include <clothlab/ext/topology.h>
#include <clothlab/plugin.h>

#include <cstring>

#include "allocation_counter.hpp"

namespace clothlab::conformance {

class PluginOnlySystem {
 public:
  explicit PluginOnlySystem(const clothlab_system& host);
  PluginOnlySystem(const PluginOnlySystem&) = delete;
  PluginOnlySystem& operator=(const PluginOnlySystem&) = delete;

  const clothlab_system& system() const { return system_; }

 private:
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

  template <class Table>
  const void* host_table() const;
  static const void* get_extension(void* self, const char* id);

  const clothlab_system& host_;
  clothlab_system system_;
  const void* host_topology_ = nullptr;
  const void* host_jacobian_ = nullptr;
  const void* host_definite_jacobian_ = nullptr;
  const void* host_cg_step_ = nullptr;
  const void* host_reductions_ = nullptr;
  const void* host_external_forces_ = nullptr;
};

}  // namespace clothlab::conformance
