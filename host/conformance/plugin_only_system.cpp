#include "plugin_only_system.hpp"

#include <cstring>

namespace clothlab::conformance {

template <>
const void* PluginOnlySystem::host_table<clothlab_topology_extension>() const {
  return host_topology_;
}
template <>
const void* PluginOnlySystem::host_table<clothlab_jacobian_extension>() const {
  return host_jacobian_;
}
template <>
const void* PluginOnlySystem::host_table<clothlab_definite_jacobian_extension>() const {
  return host_definite_jacobian_;
}
template <>
const void* PluginOnlySystem::host_table<clothlab_definite_jacobian_2_extension>() const {
  return host_definite_jacobian_2_;
}
template <>
const void* PluginOnlySystem::host_table<clothlab_cg_step_extension>() const {
  return host_cg_step_;
}
template <>
const void* PluginOnlySystem::host_table<clothlab_reductions_extension>() const {
  return host_reductions_;
}
template <>
const void* PluginOnlySystem::host_table<clothlab_external_forces_extension>() const {
  return host_external_forces_;
}
template <>
const void* PluginOnlySystem::host_table<clothlab_external_forces_2_extension>() const {
  return host_external_forces_2_;
}
template <>
const void* PluginOnlySystem::host_table<clothlab_threads_extension>() const {
  return host_threads_;
}
template <>
const void* PluginOnlySystem::host_table<clothlab_grid_extension>() const {
  return host_grid_;
}

template <>
const void* PluginOnlySystem::host_table<clothlab_contacts_extension>() const {
  return host_contacts_;
}
template <>
const void* PluginOnlySystem::host_table<clothlab_attachment_targets_extension>() const {
  return host_attachment_targets_;
}

template <>
const char* PluginOnlySystem::extension_id<clothlab_jacobian_extension>() {
  return CLOTHLAB_EXT_JACOBIAN;
}
template <>
const char* PluginOnlySystem::extension_id<clothlab_definite_jacobian_extension>() {
  return CLOTHLAB_EXT_DEFINITE_JACOBIAN;
}
template <>
const char* PluginOnlySystem::extension_id<clothlab_definite_jacobian_2_extension>() {
  return CLOTHLAB_EXT_DEFINITE_JACOBIAN_2;
}
template <>
const char* PluginOnlySystem::extension_id<clothlab_cg_step_extension>() {
  return CLOTHLAB_EXT_CG_STEP;
}

bool PluginOnlySystem::allowed_in_step(const char* call) const {
  if (!prepare_closed_) return true;
  if (misuse_.empty())
    misuse_ = std::string(call) + " called after prepare (it may allocate: prepare only)";
  return false;
}

bool PluginOnlySystem::jacobian_ready(const char* id) const {
  if (jacobian_reserved_in_prepare_) return true;
  if (misuse_.empty())
    misuse_ = std::string(id) + " used without " CLOTHLAB_EXT_JACOBIAN
                                "'s reserve in prepare (the host would allocate in step)";
  return false;
}

clothlab_status PluginOnlySystem::reserve_jacobian(void* self) {
  const allocations::Pause pause;
  auto& wrapper = *static_cast<PluginOnlySystem*>(self);
  if (!wrapper.allowed_in_step(CLOTHLAB_EXT_JACOBIAN "'s reserve"))
    return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  const auto& table = *static_cast<const clothlab_jacobian_extension*>(wrapper.host_jacobian_);
  const clothlab_status status = table.reserve(wrapper.host_.context);
  if (status == CLOTHLAB_OK) wrapper.jacobian_reserved_in_prepare_ = true;
  return status;
}

PluginOnlySystem::PluginOnlySystem(const clothlab_system& host) : host_(host), system_(host) {
  system_.context = this;
  system_.eval_acceleration = [](void* self, double t, const void* x, const void* v, void* a) {
    const allocations::Pause pause;
    const clothlab_system& host = static_cast<PluginOnlySystem*>(self)->host_;
    return host.eval_acceleration(host.context, t, x, v, a);
  };
  system_.eval_acceleration_at = [](void* self, double t, const clothlab_combination* x,
                                    const clothlab_combination* v, void* a) {
    const allocations::Pause pause;
    const clothlab_system& host = static_cast<PluginOnlySystem*>(self)->host_;
    return host.eval_acceleration_at(host.context, t, x, v, a);
  };
  system_.reserve_rkn = [](void* self, uint32_t stages) {
    const allocations::Pause pause;
    const auto& wrapper = *static_cast<PluginOnlySystem*>(self);
    if (!wrapper.allowed_in_step("reserve_rkn")) return CLOTHLAB_ERROR_INVALID_ARGUMENT;
    return wrapper.host_.reserve_rkn(wrapper.host_.context, stages);
  };
  system_.step_rkn = [](void* self, double t, double h, const clothlab_rkn_scheme* scheme) {
    const allocations::Pause pause;
    const clothlab_system& host = static_cast<PluginOnlySystem*>(self)->host_;
    return host.step_rkn(host.context, t, h, scheme);
  };
  system_.axpy = [](void* self, void* y, double alpha, const void* x) {
    const allocations::Pause pause;
    const clothlab_system& host = static_cast<PluginOnlySystem*>(self)->host_;
    host.axpy(host.context, y, alpha, x);
  };
  system_.lincomb = [](void* self, void* out, const void* base, uint32_t count,
                       const double* coefficients, const void* const* vectors) {
    const allocations::Pause pause;
    const clothlab_system& host = static_cast<PluginOnlySystem*>(self)->host_;
    host.lincomb(host.context, out, base, count, coefficients, vectors);
  };
  system_.copy = [](void* self, void* dst, const void* src) {
    const allocations::Pause pause;
    const clothlab_system& host = static_cast<PluginOnlySystem*>(self)->host_;
    host.copy(host.context, dst, src);
  };
  system_.alloc_vector = [](void* self) -> void* {
    const allocations::Pause pause;
    const auto& wrapper = *static_cast<PluginOnlySystem*>(self);
    if (!wrapper.allowed_in_step("alloc_vector")) return nullptr;
    return wrapper.host_.alloc_vector(wrapper.host_.context);
  };
  if (CLOTHLAB_HAS_FIELD(&host, clothlab_system, get_extension)) {
    host_topology_ = clothlab_system_extension(&host, CLOTHLAB_EXT_TOPOLOGY);
    host_jacobian_ = clothlab_system_extension(&host, CLOTHLAB_EXT_JACOBIAN);
    host_definite_jacobian_ = clothlab_system_extension(&host, CLOTHLAB_EXT_DEFINITE_JACOBIAN);
    host_definite_jacobian_2_ = clothlab_system_extension(&host, CLOTHLAB_EXT_DEFINITE_JACOBIAN_2);
    host_cg_step_ = clothlab_system_extension(&host, CLOTHLAB_EXT_CG_STEP);
    host_reductions_ = clothlab_system_extension(&host, CLOTHLAB_EXT_REDUCTIONS);
    host_external_forces_ = clothlab_system_extension(&host, CLOTHLAB_EXT_EXTERNAL_FORCES);
    host_external_forces_2_ = clothlab_system_extension(&host, CLOTHLAB_EXT_EXTERNAL_FORCES_2);
    host_threads_ = clothlab_system_extension(&host, CLOTHLAB_EXT_THREADS);
    host_grid_ = clothlab_system_extension(&host, CLOTHLAB_EXT_GRID);
    host_contacts_ = clothlab_system_extension(&host, CLOTHLAB_EXT_CONTACTS);
    host_attachment_targets_ = clothlab_system_extension(&host, CLOTHLAB_EXT_ATTACHMENT_TARGETS);
    system_.get_extension = &get_extension;
  }
}

const void* PluginOnlySystem::get_extension(void* self, const char* id) {
  using T = clothlab_topology_extension;
  using J = clothlab_jacobian_extension;
  using D = clothlab_definite_jacobian_extension;
  using D2 = clothlab_definite_jacobian_2_extension;
  using C = clothlab_cg_step_extension;
  using R = clothlab_reductions_extension;
  using E = clothlab_external_forces_extension;
  using E2 = clothlab_external_forces_2_extension;
  using H = clothlab_threads_extension;
  using G = clothlab_grid_extension;
  using K = clothlab_contacts_extension;
  using A = clothlab_attachment_targets_extension;
  static constexpr T topology{&Forward<T, &T::get>::call};
  static constexpr J jacobian{&reserve_jacobian, &AfterReserve<J, &J::apply>::call,
                              &AfterReserve<J, &J::diagonal_blocks>::call,
                              &AfterReserve<J, &J::pattern>::call,
                              &AfterReserve<J, &J::blocks>::call};
  static constexpr D definite_jacobian{&AfterReserve<D, &D::apply>::call,
                                       &AfterReserve<D, &D::diagonal_blocks>::call};
  static constexpr D2 definite_jacobian_2{&AfterReserve<D2, &D2::apply>::call,
                                          &AfterReserve<D2, &D2::diagonal_blocks>::call,
                                          &AfterReserve<D2, &D2::blocks>::call};
  static constexpr C cg_step{&AfterReserve<C, &C::linearise>::call,
                             &AfterReserve<C, &C::product>::call,
                             &AfterReserve<C, &C::update>::call};
  static constexpr R reductions{&Forward<R, &R::dot>::call, &Forward<R, &R::mass_dot>::call,
                                &Forward<R, &R::max_abs>::call};
  static constexpr E external_forces{&Forward<E, &E::acceleration>::call,
                                     &Forward<E, &E::depends_on_position>::call};
  static constexpr E2 external_forces_2{
      &Forward<E2, &E2::acceleration>::call, &Forward<E2, &E2::depends_on_position>::call,
      &Forward<E2, &E2::acceleration_rows>::call, &Forward<E2, &E2::depends_on_velocity>::call};
  static constexpr H threads{&Forward<H, &H::count>::call};
  static constexpr G grid{&Forward<G, &G::get>::call};
  static constexpr K contacts{&Forward<K, &K::resolve>::call};
  static constexpr A attachment_targets{&Forward<A, &A::count>::call, &Forward<A, &A::move>::call};
  const auto& wrapper = *static_cast<const PluginOnlySystem*>(self);
  if (id == nullptr) return nullptr;
  const allocations::Pause pause;
  if (clothlab_system_extension(&wrapper.host_, id) == nullptr) return nullptr;
  if (std::strcmp(id, CLOTHLAB_EXT_TOPOLOGY) == 0) return &topology;
  if (std::strcmp(id, CLOTHLAB_EXT_JACOBIAN) == 0) return &jacobian;
  if (std::strcmp(id, CLOTHLAB_EXT_DEFINITE_JACOBIAN) == 0) return &definite_jacobian;
  if (std::strcmp(id, CLOTHLAB_EXT_DEFINITE_JACOBIAN_2) == 0) return &definite_jacobian_2;
  if (std::strcmp(id, CLOTHLAB_EXT_CG_STEP) == 0) return &cg_step;
  if (std::strcmp(id, CLOTHLAB_EXT_REDUCTIONS) == 0) return &reductions;
  if (std::strcmp(id, CLOTHLAB_EXT_EXTERNAL_FORCES) == 0) return &external_forces;
  if (std::strcmp(id, CLOTHLAB_EXT_EXTERNAL_FORCES_2) == 0) return &external_forces_2;
  if (std::strcmp(id, CLOTHLAB_EXT_THREADS) == 0) return &threads;
  if (std::strcmp(id, CLOTHLAB_EXT_GRID) == 0) return &grid;
  if (std::strcmp(id, CLOTHLAB_EXT_CONTACTS) == 0) return &contacts;
  if (std::strcmp(id, CLOTHLAB_EXT_ATTACHMENT_TARGETS) == 0) return &attachment_targets;
  return nullptr;
}

}  // namespace clothlab::conformance
