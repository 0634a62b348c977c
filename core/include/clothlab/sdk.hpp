// ClothLab C++ SDK: header-only, on top of the C ABI in plugin.h.
//
// A plugin author writes an ordinary C++ class; the SDK builds the C descriptor and the
// trampolines around it. Every exception thrown inside the plugin is caught here and
// returned to the host as a status code plus message, so nothing C++ crosses the ABI.
//
//   struct MyIntegrator {
//     static constexpr const char* id = "mine";   // also name, version, description
//     static constexpr uint32_t order = 2, evals_per_step = 2;
//     static constexpr uint32_t flags = CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES;
//     static constexpr std::array<clothlab_param_spec, 0> params{};
//     explicit MyIntegrator(const clothlab::sdk::Params&);
//     template <class Real> void prepare(clothlab::sdk::System<Real>&);
//     template <class Real> void step(clothlab::sdk::System<Real>&, double t, double dt);
//   };
//
// Host extensions (ABI 1.2, clothlab/ext/): system.threads() (nothing when not offered),
// system.topology(), jacobian(), definite_jacobian(), cg_step(), reductions(), external_forces(),
// contacts() (ABI 1.3) throw CLOTHLAB_ERROR_UNSUPPORTED
// when the host lacks one; system.grid() is empty when the cloth is no grid;
// system.extension<Table>(id) returns nullptr instead. An integrator
// offers its own extensions by declaring `static constexpr clothlab_integrator_traits traits` or
// `static constexpr clothlab_explicit_scheme explicit_scheme`, and solver statistics
// (clothlab.solver-statistics/1) by a member
// `void last_step_statistics(clothlab_solver_step_statistics&) const`.
// A scenario (ABI 1.3) offers clothlab.colliders/1 by two members,
// `std::span<const clothlab_collider> colliders() const` and
// `clothlab_pose collider_pose(uint32_t index, double t) const`; clothlab.air/1 by a member
// `clothlab_air air() const`; clothlab.attachments/1 by
// `std::span<const uint32_t> attached_particles() const` and
// `void attachment_targets(double t, std::span<double> positions, std::span<double>
// velocities) const` (3 per attached particle, particle-major); and extensions the SDK has no
// glue for by a static member
// `const void* extension(std::string_view id) noexcept` returning the table for `id`, or
// nullptr; its tables' functions receive the instance as a `void*`.
//
//   CLOTHLAB_PLUGIN_ENTRY("my-plugin", "1.0.0",
//                         clothlab::sdk::integrators<MyIntegrator>,
//                         clothlab::sdk::scenarios<>)
#pragma once

#include <clothlab/ext/air.h>
#include <clothlab/ext/attachment_targets.h>
#include <clothlab/ext/attachments.h>
#include <clothlab/ext/colliders.h>
#include <clothlab/ext/explicit_scheme.h>
#include <clothlab/ext/integrator_traits.h>
#include <clothlab/ext/solver_statistics.h>
#include <clothlab/plugin.h>

#include <algorithm>
#include <array>
#include <clothlab/sdk/error.hpp>
#include <clothlab/sdk/extensions.hpp>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <exception>
#include <new>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>

namespace clothlab::sdk {

// ------------------------------------------------------------------ parameters

constexpr clothlab_param_spec real_param(const char* name, double fallback, double min_value,
                                         double max_value, const char* unit, const char* help) {
  return {sizeof(clothlab_param_spec), CLOTHLAB_PARAM_REAL, name,     help, unit,
          {fallback, 0.0, 0.0},        min_value,           max_value};
}

constexpr clothlab_param_spec int_param(const char* name, double fallback, double min_value,
                                        double max_value, const char* help) {
  return {sizeof(clothlab_param_spec), CLOTHLAB_PARAM_INT, name,     help, "",
          {fallback, 0.0, 0.0},        min_value,          max_value};
}

constexpr clothlab_param_spec bool_param(const char* name, bool fallback, const char* help) {
  return {sizeof(clothlab_param_spec),
          CLOTHLAB_PARAM_BOOL,
          name,
          help,
          "",
          {fallback ? 1.0 : 0.0, 0.0, 0.0},
          0.0,
          1.0};
}

constexpr clothlab_param_spec vec3_param(const char* name, std::array<double, 3> fallback,
                                         double min_value, double max_value, const char* unit,
                                         const char* help) {
  return {sizeof(clothlab_param_spec),
          CLOTHLAB_PARAM_VEC3,
          name,
          help,
          unit,
          {fallback[0], fallback[1], fallback[2]},
          min_value,
          max_value};
}

// Validated, typed access to the values the host passed to `create`.
class Params {
 public:
  Params(std::span<const clothlab_param_spec> specs, const clothlab_param_value* values,
         uint32_t count)
      : specs_(specs), values_(values) {
    if (count != specs.size())
      throw Error(CLOTHLAB_ERROR_INVALID_ARGUMENT, "expected " + std::to_string(specs.size()) +
                                                       " parameter values, got " +
                                                       std::to_string(count));
    if (count > 0 && values == nullptr)
      throw Error(CLOTHLAB_ERROR_INVALID_ARGUMENT, "parameter values are null");
    for (size_t i = 0; i < specs.size(); ++i) validate(specs[i], values[i]);
  }

  double real(std::string_view name) const { return find(name, CLOTHLAB_PARAM_REAL).v[0]; }
  long integer(std::string_view name) const {
    return static_cast<long>(find(name, CLOTHLAB_PARAM_INT).v[0]);
  }
  bool flag(std::string_view name) const { return find(name, CLOTHLAB_PARAM_BOOL).v[0] != 0.0; }
  std::array<double, 3> vec3(std::string_view name) const {
    const auto& value = find(name, CLOTHLAB_PARAM_VEC3);
    return {value.v[0], value.v[1], value.v[2]};
  }

 private:
  static void validate(const clothlab_param_spec& spec, const clothlab_param_value& value) {
    const int components = spec.type == CLOTHLAB_PARAM_VEC3 ? 3 : 1;
    for (int k = 0; k < components; ++k) {
      const double x = value.v[k];
      const bool integral = spec.type != CLOTHLAB_PARAM_INT && spec.type != CLOTHLAB_PARAM_BOOL
                                ? true
                                : std::floor(x) == x;
      if (!std::isfinite(x) || !integral || x < spec.min_value || x > spec.max_value) {
        char text[256];
        std::snprintf(text, sizeof text, "parameter %s = %.17g is outside [%.17g, %.17g]%s",
                      spec.name, x, spec.min_value, spec.max_value,
                      integral ? "" : " or not an integer");
        throw Error(CLOTHLAB_ERROR_INVALID_ARGUMENT, text);
      }
    }
  }

  const clothlab_param_value& find(std::string_view name, uint32_t type) const {
    for (size_t i = 0; i < specs_.size(); ++i)
      if (name == specs_[i].name && specs_[i].type == type) return values_[i];
    throw Error(CLOTHLAB_ERROR_INTERNAL, "plugin reads undeclared parameter " + std::string(name));
  }

  std::span<const clothlab_param_spec> specs_;
  const clothlab_param_value* values_;
};

// ---------------------------------------------------------------------- system

// base + sum_i coefficients[i] * vectors[i]: a stage state for System::acceleration_at.
template <class Real, size_t N>
struct Sum {
  const Real* base;
  std::array<double, N> coefficients;
  std::array<const Real*, N> vectors;
};

// An explicit Runge-Kutta-Nystrom scheme with its tables (see clothlab_rkn_scheme).
template <size_t Stages>
struct RknScheme {
  std::array<double, Stages> c, alpha;
  std::array<double, Stages * Stages> x_coupling, v_coupling;  // row-major, strictly lower
  std::array<double, Stages> x_weights, v_weights;

  constexpr clothlab_rkn_scheme raw() const {
    return {sizeof(clothlab_rkn_scheme),
            static_cast<uint32_t>(Stages),
            c.data(),
            alpha.data(),
            x_coupling.data(),
            v_coupling.data(),
            x_weights.data(),
            v_weights.data()};
  }
};

// Typed view of a clothlab_system. Vectors are Real arrays of 3 * stride elements.
template <class Real>
class System {
 public:
  explicit System(const clothlab_system& raw) : raw_(&raw) {}

  uint32_t particle_count() const { return raw_->particle_count; }
  uint32_t stride() const { return raw_->stride; }
  Real* x() const { return static_cast<Real*>(raw_->x); }
  Real* v() const { return static_cast<Real*>(raw_->v); }
  const Real* inverse_mass() const { return static_cast<const Real*>(raw_->inverse_mass); }
  std::span<const clothlab_range> active() const { return {raw_->active, raw_->active_count}; }
  const clothlab_system& raw() const { return *raw_; }

  // a = M^-1 F(t, x, v); pass v = nullptr when the integrator ignores damping forces.
  void acceleration(double t, const Real* x, const Real* v, Real* a) const {
    const clothlab_status status = raw_->eval_acceleration(raw_->context, t, x, v, a);
    if (status != CLOTHLAB_OK)
      throw Error(status, status == CLOTHLAB_ERROR_NUMERICAL ? "non-finite acceleration"
                                                             : "acceleration evaluation failed");
  }
  // a = M^-1 F(t, x, v) at a stage state given as sums, which the host forms inside the
  // force pass (ABI 1.1); e.g. acceleration_at(t, Sum<Real, 1>{x, {h}, {v}}, ...).
  template <size_t Nx, size_t Nv>
  void acceleration_at(double t, const Sum<Real, Nx>& x, const Sum<Real, Nv>& v, Real* a) const {
    static_assert(Nx <= CLOTHLAB_COMBINATION_MAX_TERMS && Nv <= CLOTHLAB_COMBINATION_MAX_TERMS);
    if (!has_acceleration_at())
      throw Error(CLOTHLAB_ERROR_UNSUPPORTED, "the host lacks eval_acceleration_at (ABI < 1.1)");
    const Combination<Nx> x_terms(x);
    const Combination<Nv> v_terms(v);
    const clothlab_status status =
        raw_->eval_acceleration_at(raw_->context, t, &x_terms.raw, &v_terms.raw, a);
    if (status != CLOTHLAB_OK)
      throw Error(status, status == CLOTHLAB_ERROR_NUMERICAL ? "non-finite acceleration"
                                                             : "acceleration evaluation failed");
  }
  bool has_acceleration_at() const {
    return CLOTHLAB_HAS_FIELD(raw_, clothlab_system, eval_acceleration_at) &&
           raw_->eval_acceleration_at != nullptr;
  }
  // Readies step_rkn for schemes of up to `stages` stages: call from `prepare` (ABI 1.1).
  void reserve_rkn(uint32_t stages) const {
    if (!has_rkn()) throw Error(CLOTHLAB_ERROR_UNSUPPORTED, "the host lacks step_rkn (ABI < 1.1)");
    const clothlab_status status = raw_->reserve_rkn(raw_->context, stages);
    if (status != CLOTHLAB_OK) throw Error(status, "reserve_rkn failed");
  }
  // One step of the scheme on x and v, fused by the host into one sweep (ABI 1.1).
  template <size_t Stages>
  void step_rkn(double t, double h, const RknScheme<Stages>& scheme) const {
    if (!has_rkn()) throw Error(CLOTHLAB_ERROR_UNSUPPORTED, "the host lacks step_rkn (ABI < 1.1)");
    const clothlab_rkn_scheme raw = scheme.raw();
    const clothlab_status status = raw_->step_rkn(raw_->context, t, h, &raw);
    if (status != CLOTHLAB_OK)
      throw Error(status, status == CLOTHLAB_ERROR_NUMERICAL ? "non-finite acceleration"
                                                             : "step_rkn failed");
  }
  bool has_rkn() const {
    return CLOTHLAB_HAS_FIELD(raw_, clothlab_system, step_rkn) && raw_->reserve_rkn != nullptr &&
           raw_->step_rkn != nullptr;
  }
  void axpy(Real* y, double alpha, const Real* x) const { raw_->axpy(raw_->context, y, alpha, x); }
  // out = base + sum c_i * v_i
  template <size_t N>
  void lincomb(Real* out, const Real* base, const std::array<double, N>& coefficients,
               const std::array<const Real*, N>& vectors) const {
    std::array<const void*, N> untyped{};
    for (size_t i = 0; i < N; ++i) untyped[i] = vectors[i];
    raw_->lincomb(raw_->context, out, base, static_cast<uint32_t>(N), coefficients.data(),
                  untyped.data());
  }
  void copy(Real* dst, const Real* src) const { raw_->copy(raw_->context, dst, src); }

  // The host extension `id` (a clothlab/ext/ header's CLOTHLAB_EXT_* id) as its function
  // table, or nullptr when the host does not offer it or predates extensions (ABI < 1.2).
  template <class Table>
  const Table* extension(const char* id) const {
    return static_cast<const Table*>(clothlab_system_extension(raw_, id));
  }
  // The thread count the host lets this system's work use (clothlab.threads/1): a plugin's
  // own parallel loops keep to it. Nothing when the host does not say.
  std::optional<uint32_t> threads() const {
    const auto* table = extension<clothlab_threads_extension>(CLOTHLAB_EXT_THREADS);
    if (table == nullptr) return std::nullopt;
    return table->count(raw_->context);
  }
  // The typed extensions; each throws CLOTHLAB_ERROR_UNSUPPORTED when the host lacks it.
  // topology()'s first call may allocate: make it from `prepare`.
  Topology topology() const {
    clothlab_topology out{};
    out.struct_size = sizeof out;
    check(required<clothlab_topology_extension>(CLOTHLAB_EXT_TOPOLOGY).get(raw_->context, &out),
          "topology failed");
    return Topology(out);
  }
  // The grid the cloth is laid out on (clothlab.grid/1), or nothing when the host does not say
  // it is one. Its first call may allocate: make it from `prepare`.
  std::optional<Grid> grid() const {
    const auto* table = extension<clothlab_grid_extension>(CLOTHLAB_EXT_GRID);
    if (table == nullptr) return std::nullopt;
    clothlab_grid out{};
    out.struct_size = sizeof out;
    check(table->get(raw_->context, &out), "grid failed");
    return Grid(out);
  }
  Jacobian<Real> jacobian() const {
    return {required<clothlab_jacobian_extension>(CLOTHLAB_EXT_JACOBIAN), raw_->context};
  }
  DefiniteJacobian<Real> definite_jacobian() const {
    return {required<clothlab_definite_jacobian_extension>(CLOTHLAB_EXT_DEFINITE_JACOBIAN),
            raw_->context,
            extension<clothlab_definite_jacobian_2_extension>(CLOTHLAB_EXT_DEFINITE_JACOBIAN_2)};
  }
  CgStep<Real> cg_step() const {
    return {required<clothlab_cg_step_extension>(CLOTHLAB_EXT_CG_STEP), raw_->context};
  }
  Reductions<Real> reductions() const {
    return {required<clothlab_reductions_extension>(CLOTHLAB_EXT_REDUCTIONS), raw_->context};
  }
  ExternalForces<Real> external_forces() const {
    return {required<clothlab_external_forces_extension>(CLOTHLAB_EXT_EXTERNAL_FORCES),
            raw_->context,
            extension<clothlab_external_forces_2_extension>(CLOTHLAB_EXT_EXTERNAL_FORCES_2)};
  }
  Contacts<Real> contacts() const {
    return {required<clothlab_contacts_extension>(CLOTHLAB_EXT_CONTACTS), raw_->context};
  }
  // Keeps x and v out of the scene's colliders at time t when the host offers
  // clothlab.contacts/1; a no-op on a host without it, which has no colliders to keep out of.
  void resolve_contacts(double t) const {
    if (extension<clothlab_contacts_extension>(CLOTHLAB_EXT_CONTACTS) != nullptr)
      contacts().resolve(t, x(), v());
  }
  // Whether the scene has attached particles (clothlab.attachment-targets/1), which
  // move_attachments moves; false on a host without the extension.
  bool has_attachments() const {
    const auto* table =
        extension<clothlab_attachment_targets_extension>(CLOTHLAB_EXT_ATTACHMENT_TARGETS);
    return table != nullptr && table->count(raw_->context) != 0;
  }
  // Sets the attached particles of x and v to their targets at time t; a no-op on a host
  // without clothlab.attachment-targets/1 or on a scene without attachments.
  void move_attachments(double t) const { move_attachments(t, x(), v()); }
  // The same on any two vectors of the system (a state a method combines before its solve).
  void move_attachments(double t, Real* positions, Real* velocities) const {
    const auto* table =
        extension<clothlab_attachment_targets_extension>(CLOTHLAB_EXT_ATTACHMENT_TARGETS);
    if (table != nullptr && table->count(raw_->context) != 0)
      check(table->move(raw_->context, t, positions, velocities), "moving the attachments failed");
  }
  Real* alloc_vector() const {
    void* p = raw_->alloc_vector(raw_->context);
    if (p == nullptr) throw std::bad_alloc();
    return static_cast<Real*>(p);
  }

 private:
  template <size_t N>
  struct Combination {
    explicit Combination(const Sum<Real, N>& sum) {
      for (size_t i = 0; i < N; ++i) untyped[i] = sum.vectors[i];
      raw = {sum.base, static_cast<uint32_t>(N), 0, sum.coefficients.data(), untyped.data()};
    }
    std::array<const void*, N> untyped{};
    clothlab_combination raw;
  };

  template <class Table>
  const Table& required(const char* id) const {
    const Table* table = extension<Table>(id);
    if (table == nullptr)
      throw Error(CLOTHLAB_ERROR_UNSUPPORTED, std::string("the host lacks ") + id);
    return *table;
  }

  const clothlab_system* raw_;
};

constexpr uint32_t both_precisions = (1u << CLOTHLAB_FLOAT32) | (1u << CLOTHLAB_FLOAT64);

// Calls body(System<float>&) or body(System<double>&) for the system's precision.
template <class Body>
void with_precision(const clothlab_system& raw, Body&& body) {
  if (raw.precision == CLOTHLAB_FLOAT32) {
    System<float> system(raw);
    body(system);
  } else if (raw.precision == CLOTHLAB_FLOAT64) {
    System<double> system(raw);
    body(system);
  } else {
    throw Error(CLOTHLAB_ERROR_UNSUPPORTED, "unknown precision " + std::to_string(raw.precision));
  }
}

// ------------------------------------------------------------ descriptor glue

// An integrator's extensions: `static constexpr clothlab_integrator_traits traits` and
// `static constexpr clothlab_explicit_scheme explicit_scheme` in the Impl class, when
// declared (see explicit_scheme_of below), and clothlab.solver-statistics/1 when Impl has
// `void last_step_statistics(clothlab_solver_step_statistics&) const`; NULL for any other id.
template <class Impl>
const void* integrator_extension(const char* id) noexcept {
  if (id == nullptr) return nullptr;
  if constexpr (requires { Impl::traits; }) {
    static_assert(
        std::is_same_v<std::remove_cv_t<decltype(Impl::traits)>, clothlab_integrator_traits>);
    if (std::strcmp(id, CLOTHLAB_EXT_INTEGRATOR_TRAITS) == 0) return &Impl::traits;
  }
  if constexpr (requires { Impl::explicit_scheme; }) {
    static_assert(std::is_same_v<std::remove_cv_t<decltype(Impl::explicit_scheme)>,
                                 clothlab_explicit_scheme>);
    if (std::strcmp(id, CLOTHLAB_EXT_EXPLICIT_SCHEME) == 0) return &Impl::explicit_scheme;
  }
  if constexpr (requires(const Impl& impl, clothlab_solver_step_statistics& out) {
                  impl.last_step_statistics(out);
                }) {
    static const clothlab_solver_statistics_extension statistics{
        [](void* instance, clothlab_solver_step_statistics* out) -> clothlab_status {
          if (instance == nullptr || out == nullptr ||
              out->struct_size < sizeof(clothlab_solver_step_statistics))
            return CLOTHLAB_ERROR_INVALID_ARGUMENT;
          static_cast<const Impl*>(instance)->last_step_statistics(*out);
          out->struct_size = sizeof(clothlab_solver_step_statistics);
          return CLOTHLAB_OK;
        }};
    if (std::strcmp(id, CLOTHLAB_EXT_SOLVER_STATISTICS) == 0) return &statistics;
  }
  return nullptr;
}

// The explicit-scheme extension for a scheme table held in a static constexpr raw scheme:
//   static constexpr clothlab_rkn_scheme raw_scheme = scheme.raw();
//   static constexpr clothlab_explicit_scheme explicit_scheme = explicit_scheme_of(raw_scheme);
constexpr clothlab_explicit_scheme explicit_scheme_of(const clothlab_rkn_scheme& scheme,
                                                      bool first_same_as_last = false) {
  return {sizeof(clothlab_explicit_scheme), first_same_as_last ? 1u : 0u, &scheme};
}

template <class Impl>
const clothlab_integrator* integrator_descriptor() {
  static const clothlab_integrator descriptor = {
      sizeof(clothlab_integrator),
      Impl::flags,
      Impl::id,
      Impl::name,
      Impl::version,
      Impl::description,
      Impl::order,
      Impl::evals_per_step,
      both_precisions,
      static_cast<uint32_t>(Impl::params.size()),
      Impl::params.data(),
      [](const clothlab_param_value* values, uint32_t count, void** out,
         clothlab_message* error) -> clothlab_status {
        return guarded(error, [&] {
          if (out == nullptr) throw Error(CLOTHLAB_ERROR_INVALID_ARGUMENT, "out_instance is null");
          *out = new Impl(Params(Impl::params, values, count));
        });
      },
      [](void* instance, const clothlab_system* raw, clothlab_message* error) -> clothlab_status {
        return guarded(error, [&] {
          with_precision(*raw,
                         [&](auto& system) { static_cast<Impl*>(instance)->prepare(system); });
        });
      },
      [](void* instance, const clothlab_system* raw, double t, double dt,
         clothlab_message* error) -> clothlab_status {
        return guarded(error, [&] {
          if (!std::isfinite(dt) || dt < 0.0)
            throw Error(CLOTHLAB_ERROR_INVALID_ARGUMENT, "dt must be finite and >= 0");
          with_precision(*raw,
                         [&](auto& system) { static_cast<Impl*>(instance)->step(system, t, dt); });
        });
      },
      [](void* instance) { delete static_cast<Impl*>(instance); },
      &integrator_extension<Impl>,
  };
  return &descriptor;
}

namespace detail {

template <class Impl>
uint32_t collider_count(void* instance) {
  return static_cast<uint32_t>(static_cast<const Impl*>(instance)->colliders().size());
}

template <class Impl>
clothlab_status describe_collider(void* instance, uint32_t index, clothlab_collider* out,
                                  clothlab_message* error) {
  return guarded(error, [&] {
    const std::span<const clothlab_collider> all = static_cast<const Impl*>(instance)->colliders();
    if (out == nullptr || out->struct_size < sizeof(clothlab_collider) || index >= all.size())
      throw Error(CLOTHLAB_ERROR_INVALID_ARGUMENT,
                  "collider " + std::to_string(index) + ": no such collider or buffer");
    *out = all[index];
    out->struct_size = sizeof(clothlab_collider);
  });
}

// Collider `index`'s answer at t from `answer(impl)` into *out, after checking both.
template <class Impl, class Out, class Answer>
clothlab_status collider_answer(void* instance, uint32_t index, Out* out, clothlab_message* error,
                                Answer&& answer) {
  return guarded(error, [&] {
    const Impl& impl = *static_cast<const Impl*>(instance);
    if (out == nullptr || index >= impl.colliders().size())
      throw Error(CLOTHLAB_ERROR_INVALID_ARGUMENT,
                  "collider " + std::to_string(index) + ": no such collider");
    *out = answer(impl);
  });
}

}  // namespace detail

// A scenario's extensions: clothlab.colliders/1 when its class has colliders() and
// collider_pose(); clothlab.colliders/2 and /1 when it has colliders() and collider_motion()
// (a pose with its velocity); clothlab.air/1 when it has air(), and those it returns from a
// static member `const void* extension(std::string_view id) noexcept`; NULL for any other id.
template <class Impl>
const void* scenario_extension(const char* id) noexcept {
  if (id == nullptr) return nullptr;
  if constexpr (requires(const Impl& impl, uint32_t index, double t) {
                  { impl.colliders() } -> std::convertible_to<std::span<const clothlab_collider>>;
                  { impl.collider_pose(index, t) } -> std::same_as<clothlab_pose>;
                }) {
    static const clothlab_colliders_extension colliders{
        &detail::collider_count<Impl>, &detail::describe_collider<Impl>,
        [](void* instance, uint32_t index, double t, clothlab_pose* out,
           clothlab_message* error) -> clothlab_status {
          return detail::collider_answer<Impl>(instance, index, out, error, [&](const Impl& impl) {
            return impl.collider_pose(index, t);
          });
        }};
    if (std::strcmp(id, CLOTHLAB_EXT_COLLIDERS) == 0) return &colliders;
  }
  if constexpr (requires(const Impl& impl, uint32_t index, double t) {
                  { impl.colliders() } -> std::convertible_to<std::span<const clothlab_collider>>;
                  { impl.collider_motion(index, t) } -> std::same_as<clothlab_collider_motion>;
                }) {
    static const clothlab_colliders_extension_2 moving{
        &detail::collider_count<Impl>, &detail::describe_collider<Impl>,
        [](void* instance, uint32_t index, double t, clothlab_collider_motion* out,
           clothlab_message* error) -> clothlab_status {
          return detail::collider_answer<Impl>(instance, index, out, error, [&](const Impl& impl) {
            return impl.collider_motion(index, t);
          });
        }};
    static const clothlab_colliders_extension posed{
        &detail::collider_count<Impl>, &detail::describe_collider<Impl>,
        [](void* instance, uint32_t index, double t, clothlab_pose* out,
           clothlab_message* error) -> clothlab_status {
          return detail::collider_answer<Impl>(instance, index, out, error, [&](const Impl& impl) {
            return impl.collider_motion(index, t).pose;
          });
        }};
    if (std::strcmp(id, CLOTHLAB_EXT_COLLIDERS_2) == 0) return &moving;
    if (std::strcmp(id, CLOTHLAB_EXT_COLLIDERS) == 0) return &posed;
  }
  if constexpr (requires(const Impl& impl, double t, std::span<double> out) {
                  { impl.attached_particles() } -> std::convertible_to<std::span<const uint32_t>>;
                  impl.attachment_targets(t, out, out);
                }) {
    static const clothlab_attachments_extension attachments{
        [](void* instance) -> uint32_t {
          return static_cast<uint32_t>(
              static_cast<const Impl*>(instance)->attached_particles().size());
        },
        [](void* instance, uint32_t* out, clothlab_message* error) -> clothlab_status {
          return guarded(error, [&] {
            const std::span<const uint32_t> all =
                static_cast<const Impl*>(instance)->attached_particles();
            if (out == nullptr && !all.empty())
              throw Error(CLOTHLAB_ERROR_INVALID_ARGUMENT, "attachments: no buffer");
            std::copy(all.begin(), all.end(), out);
          });
        },
        [](void* instance, double t, double* positions, double* velocities,
           clothlab_message* error) -> clothlab_status {
          return guarded(error, [&] {
            const Impl& impl = *static_cast<const Impl*>(instance);
            const std::size_t values = 3 * impl.attached_particles().size();
            if ((positions == nullptr || velocities == nullptr) && values != 0)
              throw Error(CLOTHLAB_ERROR_INVALID_ARGUMENT, "attachment targets: no buffer");
            impl.attachment_targets(t, std::span<double>(positions, values),
                                    std::span<double>(velocities, values));
          });
        }};
    if (std::strcmp(id, CLOTHLAB_EXT_ATTACHMENTS) == 0) return &attachments;
  }
  if constexpr (requires(const Impl& impl) {
                  { impl.air() } -> std::same_as<clothlab_air>;
                }) {
    static const clothlab_air_extension air{
        [](void* instance, clothlab_air* out, clothlab_message* error) -> clothlab_status {
          return guarded(error, [&] {
            if (out == nullptr || out->struct_size < sizeof(clothlab_air))
              throw Error(CLOTHLAB_ERROR_INVALID_ARGUMENT, "air: buffer too small");
            *out = static_cast<const Impl*>(instance)->air();
            out->struct_size = sizeof(clothlab_air);
          });
        }};
    if (std::strcmp(id, CLOTHLAB_EXT_AIR) == 0) return &air;
  }
  if constexpr (requires(std::string_view name) {
                  { Impl::extension(name) }
                  noexcept->std::same_as<const void*>;
                })
    return Impl::extension(id);
  return nullptr;
}

template <class Impl>
const clothlab_scenario* scenario_descriptor() {
  static const clothlab_scenario descriptor = {
      sizeof(clothlab_scenario),
      0,
      Impl::id,
      Impl::name,
      Impl::version,
      Impl::description,
      static_cast<uint32_t>(Impl::params.size()),
      0,
      Impl::params.data(),
      [](const clothlab_param_value* values, uint32_t count, void** out,
         clothlab_message* error) -> clothlab_status {
        return guarded(error, [&] {
          if (out == nullptr) throw Error(CLOTHLAB_ERROR_INVALID_ARGUMENT, "out_instance is null");
          *out = new Impl(Params(Impl::params, values, count));
        });
      },
      [](void* instance, clothlab_scene* scene, clothlab_message* error) -> clothlab_status {
        return guarded(error, [&] {
          // Every clothlab_scene field dates from 1.0: a 1.0-sized buffer holds them all.
          if (scene == nullptr || scene->struct_size < CLOTHLAB_SCENE_SIZE_1_0)
            throw Error(CLOTHLAB_ERROR_INVALID_ARGUMENT, "scene buffer too small");
          static_cast<const Impl*>(instance)->describe(*scene);
        });
      },
      [](void* instance) { delete static_cast<Impl*>(instance); },
      &scenario_extension<Impl>,
  };
  return &descriptor;
}

template <class... Impl>
struct integrators {
  static constexpr uint32_t count = sizeof...(Impl);
  static const clothlab_integrator* const* list() {
    static const clothlab_integrator* const items[count + 1] = {integrator_descriptor<Impl>()...,
                                                                nullptr};
    return count ? items : nullptr;
  }
};

template <class... Impl>
struct scenarios {
  static constexpr uint32_t count = sizeof...(Impl);
  static const clothlab_scenario* const* list() {
    static const clothlab_scenario* const items[count + 1] = {scenario_descriptor<Impl>()...,
                                                              nullptr};
    return count ? items : nullptr;
  }
};

template <class Integrators, class Scenarios>
const clothlab_plugin_descriptor* plugin_descriptor(const char* library_name,
                                                    const char* library_version) {
  static const clothlab_plugin_descriptor descriptor = {
      {CLOTHLAB_ABI_VERSION_MAJOR, CLOTHLAB_ABI_VERSION_MINOR},
      sizeof(clothlab_plugin_descriptor),
      Integrators::count,
      Scenarios::count,
      0,
      library_name,
      library_version,
      Integrators::list(),
      Scenarios::list(),
  };
  return &descriptor;
}

}  // namespace clothlab::sdk

// Defines the library's one exported symbol.
#define CLOTHLAB_PLUGIN_ENTRY(LIBRARY_NAME, LIBRARY_VERSION, INTEGRATORS, SCENARIOS)         \
  extern "C" CLOTHLAB_EXPORT const clothlab_plugin_descriptor* clothlab_plugin_entry(void) { \
    return clothlab::sdk::plugin_descriptor<INTEGRATORS, SCENARIOS>(LIBRARY_NAME,            \
                                                                    LIBRARY_VERSION);        \
  }
