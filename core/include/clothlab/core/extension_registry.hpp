// Every extension id the ABI publishes (clothlab/ext/), with the side that offers it: the one
// list the host's parts check their get_extension answers against. A table that hands out
// extensions (the engine, the reference system, the conformance runner's interposer, a test
// host) answers each id of its side or names it among the ids it declines; the registry tests
// fail for a new id until every such table has decided.
#pragma once

#include <clothlab/ext/air.h>
#include <clothlab/ext/attachment_targets.h>
#include <clothlab/ext/attachments.h>
#include <clothlab/ext/cg_step.h>
#include <clothlab/ext/colliders.h>
#include <clothlab/ext/contacts.h>
#include <clothlab/ext/definite_jacobian.h>
#include <clothlab/ext/explicit_scheme.h>
#include <clothlab/ext/external_forces.h>
#include <clothlab/ext/grid.h>
#include <clothlab/ext/integrator_traits.h>
#include <clothlab/ext/jacobian.h>
#include <clothlab/ext/mesh.h>
#include <clothlab/ext/reductions.h>
#include <clothlab/ext/solver_statistics.h>
#include <clothlab/ext/text_parameters.h>
#include <clothlab/ext/threads.h>
#include <clothlab/ext/topology.h>

#include <algorithm>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace clothlab {

// Who offers an extension: the host to an integrator (clothlab_system), an integrator to the
// host (clothlab_integrator), a scenario to the host (clothlab_scenario), or any plugin, an
// integrator or a scenario, to the host (Plugin: an id of both plugin sides).
enum class ExtensionSide { Host, Integrator, Scenario, Plugin };

std::string_view to_string(ExtensionSide side);

struct PublishedExtension {
  const char* id;
  ExtensionSide side;
};

inline constexpr PublishedExtension kPublishedExtensions[] = {
    {CLOTHLAB_EXT_TOPOLOGY, ExtensionSide::Host},
    {CLOTHLAB_EXT_GRID, ExtensionSide::Host},
    {CLOTHLAB_EXT_JACOBIAN, ExtensionSide::Host},
    {CLOTHLAB_EXT_DEFINITE_JACOBIAN, ExtensionSide::Host},
    {CLOTHLAB_EXT_DEFINITE_JACOBIAN_2, ExtensionSide::Host},
    {CLOTHLAB_EXT_CG_STEP, ExtensionSide::Host},
    {CLOTHLAB_EXT_REDUCTIONS, ExtensionSide::Host},
    {CLOTHLAB_EXT_EXTERNAL_FORCES, ExtensionSide::Host},
    {CLOTHLAB_EXT_EXTERNAL_FORCES_2, ExtensionSide::Host},
    {CLOTHLAB_EXT_THREADS, ExtensionSide::Host},
    {CLOTHLAB_EXT_CONTACTS, ExtensionSide::Host},
    {CLOTHLAB_EXT_ATTACHMENT_TARGETS, ExtensionSide::Host},
    {CLOTHLAB_EXT_INTEGRATOR_TRAITS, ExtensionSide::Integrator},
    {CLOTHLAB_EXT_EXPLICIT_SCHEME, ExtensionSide::Integrator},
    {CLOTHLAB_EXT_SOLVER_STATISTICS, ExtensionSide::Integrator},
    {CLOTHLAB_EXT_COLLIDERS, ExtensionSide::Scenario},
    {CLOTHLAB_EXT_COLLIDERS_2, ExtensionSide::Scenario},
    {CLOTHLAB_EXT_ATTACHMENTS, ExtensionSide::Scenario},
    {CLOTHLAB_EXT_AIR, ExtensionSide::Scenario},
    {CLOTHLAB_EXT_MESH, ExtensionSide::Scenario},
    {CLOTHLAB_EXT_TEXT_PARAMETERS, ExtensionSide::Plugin},
};

inline std::string_view to_string(ExtensionSide side) {
  switch (side) {
    case ExtensionSide::Host:
      return "host";
    case ExtensionSide::Integrator:
      return "integrator";
    case ExtensionSide::Scenario:
      return "scenario";
    case ExtensionSide::Plugin:
      return "plugin";
  }
  return "?";
}

// The ids a table of `side` may answer: a Plugin id belongs to the integrator and the scenario
// sides alike.
inline std::vector<const char*> published_ids(ExtensionSide side) {
  const auto belongs = [side](ExtensionSide of) {
    return of == side || (of == ExtensionSide::Plugin && side != ExtensionSide::Host);
  };
  std::vector<const char*> ids;
  for (const PublishedExtension& extension : kPublishedExtensions)
    if (belongs(extension.side)) ids.push_back(extension.id);
  return ids;
}

inline bool is_published(std::string_view id) {
  return std::any_of(std::begin(kPublishedExtensions), std::end(kPublishedExtensions),
                     [id](const PublishedExtension& e) { return id == e.id; });
}

// Ids no table may answer, built from the published ones of `side`: each name at the revision
// above and below its own and without one, an unknown name and the empty id.
inline std::vector<std::string> unpublished_ids(ExtensionSide side) {
  std::vector<std::string> ids = {"clothlab.no-such-extension/1", ""};
  for (const char* published : published_ids(side)) {
    const std::string_view id = published;
    const std::size_t slash = id.rfind('/');
    const std::string name(id.substr(0, slash));
    const int revision = std::stoi(std::string(id.substr(slash + 1)));
    for (const std::string& other : {name + "/" + std::to_string(revision + 1),
                                     name + "/" + std::to_string(revision - 1), name})
      if (!is_published(other) && std::find(ids.begin(), ids.end(), other) == ids.end())
        ids.push_back(other);
  }
  return ids;
}

// What is wrong with a table's answers, "" when nothing: every published id of `side` answered
// by `lookup` or in `declined` (not both), every id in `declined` published, and no unpublished
// id answered. `who` names the table in the message.
inline std::string extension_coverage(std::string_view who, ExtensionSide side,
                                      const std::function<const void*(const char*)>& lookup,
                                      std::span<const char* const> declined) {
  const auto declines = [&](std::string_view id) {
    return std::any_of(declined.begin(), declined.end(), [id](const char* d) { return id == d; });
  };
  std::string problems;
  const auto report = [&](const std::string& problem) {
    problems += (problems.empty() ? std::string(who) + ": " : std::string("; ")) + problem;
  };
  for (const char* id : declined)
    if (!is_published(id)) report("declines " + std::string(id) + ", which is not published");
  for (const char* id : published_ids(side)) {
    const bool answered = lookup(id) != nullptr;
    if (answered && declines(id)) report("answers " + std::string(id) + ", which it declines");
    if (!answered && !declines(id))
      report("neither answers nor declines " + std::string(id) + " (a " +
             std::string(to_string(side)) + " extension)");
  }
  for (const std::string& id : unpublished_ids(side))
    if (lookup(id.c_str()) != nullptr) report("answers \"" + id + "\", which is not published");
  return problems;
}

}  // namespace clothlab
