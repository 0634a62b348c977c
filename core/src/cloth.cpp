#include <clothlab/core/cloth.hpp>
#include <clothlab/core/cloth_model.hpp>

#include "engine.hpp"

namespace clothlab {

namespace {

SpringCounts count_families(const ClothModel& model) {
  SpringCounts counts;
  for (uint8_t family : model.family) {
    if (family == CLOTHLAB_SPRING_STRUCTURAL) ++counts.structural;
    if (family == CLOTHLAB_SPRING_SHEAR) ++counts.shear;
    if (family == CLOTHLAB_SPRING_FLEXION) ++counts.flexion;
  }
  return counts;
}

}  // namespace

struct Cloth::Impl {
  Scene scene;
  Precision precision;
  SpringCounts springs;
  std::shared_ptr<const ClothModel> model;
  std::unique_ptr<detail::Engine> engine;
};

Cloth::Cloth(const Scene& scene, Precision precision, PipelineOptions options)
    : Cloth(scene, build_grid_model(scene), precision, options) {}

Cloth::Cloth(const Scene& scene, std::shared_ptr<const ClothModel> model, Precision precision,
             PipelineOptions options)
    : impl_(std::make_unique<Impl>(
          Impl{scene, precision,
               model->grid ? count_springs(model->grid->rows, model->grid->cols)
                           : count_families(*model),
               model, detail::make_engine(scene, model, precision, options)})) {}

Cloth::~Cloth() = default;

const clothlab_system& Cloth::system() const { return impl_->engine->system(); }
const Scene& Cloth::scene() const { return impl_->scene; }
const std::shared_ptr<const ClothModel>& Cloth::model() const { return impl_->model; }
Precision Cloth::precision() const { return impl_->precision; }
uint32_t Cloth::particle_count() const { return impl_->engine->system().particle_count; }
const SpringCounts& Cloth::springs() const { return impl_->springs; }
int Cloth::threads() const { return impl_->engine->threads(); }
void Cloth::begin_step() { impl_->engine->begin_step(); }
void Cloth::end_step() { impl_->engine->end_step(); }

const StageCounters& Cloth::counters() const { return impl_->engine->counters(); }
void Cloth::reset_counters() { impl_->engine->counters() = StageCounters{}; }

void Cloth::positions(std::vector<double>& out) const { impl_->engine->positions(out); }
void Cloth::velocities(std::vector<double>& out) const { impl_->engine->velocities(out); }
void Cloth::positions(std::vector<float>& out) const { impl_->engine->positions(out); }
void Cloth::velocities(std::vector<float>& out) const { impl_->engine->velocities(out); }
void Cloth::set_state(const std::vector<double>& x, const std::vector<double>& v) {
  impl_->engine->set_state(x, v);
}
void Cloth::copy_raw_state(RawState& out) const { impl_->engine->copy_raw_state(out); }
void Cloth::set_raw_state(const RawState& state) { impl_->engine->set_raw_state(state); }
bool Cloth::state_is_finite() const { return impl_->engine->state_is_finite(); }
Cloth::Energy Cloth::energy() const { return impl_->engine->energy(); }
Cloth::Stretch Cloth::stretch(Springs springs) const { return impl_->engine->stretch(springs); }
double Cloth::stretch_percentile(Springs springs, double fraction) const {
  return impl_->engine->stretch_percentile(springs, fraction);
}
Cloth::LongestSpring Cloth::longest_spring(Springs springs) const {
  return impl_->engine->longest_spring(springs);
}
void Cloth::set_colliders(std::span<const Collider> colliders, double t) {
  impl_->engine->set_colliders(colliders, t);
}
Cloth::Contacts Cloth::contacts() const { return impl_->engine->contacts(); }
std::span<const Collider> Cloth::colliders() const { return impl_->engine->colliders(); }
void Cloth::set_attachments(std::span<const uint32_t> particles, AttachmentSource& source) {
  impl_->engine->set_attachments(particles, source);
}
bool Cloth::move_attachments(double t) { return impl_->engine->move_attachments(t); }
void Cloth::pin_loads(PinLoads& out) const { impl_->engine->pin_loads(out); }
Cloth::Momentum Cloth::free_momentum() const { return impl_->engine->free_momentum(); }
double Cloth::contact_work() const { return impl_->engine->contact_work(); }

}  // namespace clothlab
