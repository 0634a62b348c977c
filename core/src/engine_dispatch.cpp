// make_engine: the engine of the SIMD target that runs here (simd_target). The engine's sources
// are compiled once with the build's flags (`baseline`: the portable target, or native) and, in
// a portable build, once more per wider target (core/CMakeLists.txt), each copy in a namespace
// of its own (simd_namespace.hpp).
#include <clothlab/core/cloth.hpp>
#include <clothlab/core/simd.hpp>
#include <clothlab/sdk/simd_target.hpp>
#include <stdexcept>

#include "engine.hpp"

namespace clothlab {
namespace detail {

#define CLOTHLAB_DECLARE_ENGINE(target)                                                 \
  std::unique_ptr<Engine> make_engine_##target(const Scene& scene,                      \
                                               std::shared_ptr<const ClothModel> model, \
                                               Precision precision, PipelineOptions options);
CLOTHLAB_DECLARE_ENGINE(baseline)
#if defined(CLOTHLAB_SIMD_WITH_AVX2)
CLOTHLAB_DECLARE_ENGINE(avx2)
#endif
#if defined(CLOTHLAB_SIMD_WITH_AVX512)
CLOTHLAB_DECLARE_ENGINE(avx512)
#endif
#undef CLOTHLAB_DECLARE_ENGINE

std::unique_ptr<Engine> make_engine(const Scene& scene, std::shared_ptr<const ClothModel> model,
                                    Precision precision, PipelineOptions options) {
  // Throws for a CLOTHLAB_SIMD that cannot run, also where the build has one target only.
  [[maybe_unused]] const std::string_view target = simd_target();
#if defined(CLOTHLAB_SIMD_WITH_AVX512)
  if (target == "avx512") return make_engine_avx512(scene, std::move(model), precision, options);
#endif
#if defined(CLOTHLAB_SIMD_WITH_AVX2)
  if (target == "avx2") return make_engine_avx2(scene, std::move(model), precision, options);
#endif
  return make_engine_baseline(scene, std::move(model), precision, options);
}

}  // namespace detail

std::span<const std::string_view> simd_targets_built() { return sdk::kBuiltSimdTargets; }

std::string_view simd_target() {
  const sdk::SimdChoice choice = sdk::choose_simd_target(sdk::kBuiltSimdTargets);
  if (choice.target.empty()) throw std::invalid_argument(choice.error);
  return choice.target;
}

}  // namespace clothlab
