#pragma once
// Every field of DescriptorRecipe (spherical-map options, SH fit options, feature pipeline, off-recipe policy),
// listed ONCE in visit_recipe() with the recipe version that introduced it, so that the model file writes all of
// them, reads all of them back and computes the version it writes from them: a model must reproduce the descriptor
// it was trained on exactly (docs/design/classification.md: never silently mismatched). This list is the recipe's version table.
//
// Versions (DescriptorRecipe::kVersion is the newest):
//   1  the first recipe (issue 12): every field written without a version below.
//   2  map.verification.strict_conformal_bound, map.laplacian, map.flow_budget_seconds (added 2026-12-01 with a
//      legacy value but without a bump), map.area_correction (the bump).
//   3  map.chain_budget_seconds, map.linear_reserve_seconds, map.cmcf.stall_patience (added 2026-12-02 without a
//      bump, so a version-2 build read such files with its own defaults; issue 27).
//   4  features.spectrum_count (legacy 0: no spectrum) and the feature families spectrum, spectrum_global, canonical_sh,
//      canonical_sh_global, all (issue 38): a file with one of those families is of version 4 whatever its fields
//      (feature_family_version), so an older reader refuses it by number.
//   5  map.canonical (the canonical map the descriptor is computed on, issue 37) and sh.sampling (vertex or surface
//      samples of the SH fit).
// Retired: map.min_fallback_flow_seconds (in version-2 files of 2026-12-02; 0 is what this build computes).
//
// The version a file gets (recipe_version_of): the highest version that introduced a field whose value differs
// from its legacy value (how descriptors were computed before the field existed); version-1 fields count as 1. The
// file then holds exactly the fields of that version: a later field at its legacy value is left out, so a reader of
// that version reads the file, and a reader of an older version refuses it by its number.
//
// Adding a field: one line here with the next version and its legacy value, and kVersion raised to it.
// tests/classify/recipe_versions_test.cpp fails when a member of the recipe's structs has no line here.
//
// A visitor provides, for fields of version 1: field(key, value&) (double, int, bool or an enum) and
// group(key, fill) for nesting; for later ones: added(version, key, value&, legacy) and
// added_group(version, key, fill, target&, legacy); and retired(key, last_version, value_meaning_today) for keys
// older files may carry that no field reads any more; derived(key) for a key computed from the fields.

#include "core/classify/descriptor_recipe.hpp"

namespace wish {

template <class Visitor, class Recipe>
void visit_recipe(Visitor& v, Recipe& d) {
  v.group("map", [&](Visitor& m) {
    m.field("method", d.map.method);
    m.group("willmore", [&](Visitor& w) {
      auto& o = d.map.willmore;
      w.field("tau", o.tau);
      w.field("max_steps", o.max_steps);
      w.field("roundness_tolerance", o.roundness_tolerance);
      w.field("energy_tolerance", o.energy_tolerance);
      w.field("roundness_stall", o.roundness_stall);
      w.field("roundness_stall_energy", o.roundness_stall_energy);
      w.field("min_tau", o.min_tau);
      w.field("filtered", o.filtered);
      w.field("filter_strength", o.filter_strength);
      w.field("max_inverse_iterations", o.max_inverse_iterations);
      w.field("max_eigen_residual", o.max_eigen_residual);
      w.field("energy_increase_tolerance", o.energy_increase_tolerance);
      w.field("complex_dirac", o.complex_dirac);
    });
    m.group("cmcf", [&](Visitor& c) {
      auto& o = d.map.cmcf;
      c.field("delta", o.delta);
      c.field("max_steps", o.max_steps);
      c.field("roundness_tolerance", o.roundness_tolerance);
      c.field("roundness_stall", o.roundness_stall);
      c.field("min_steps_before_stall", o.min_steps_before_stall);
      c.field("fallback_max_steps", o.fallback_max_steps);
      // Older files stopped at the first step that did not lower R (and flowed to their last surface).
      c.added(3, "stall_patience", o.stall_patience, 1);
    });
    m.group("linear", [&](Visitor& l) {
      l.field("min_weight", d.map.linear.min_weight);
      l.field("always_clamp", d.map.linear.always_clamp);
    });
    m.field("solver", d.map.solver);
    m.field("fallback", d.map.fallback);
    m.field("untangle", d.map.untangle);
    m.group("verification", [&](Visitor& q) {
      q.field("degenerate_height", d.map.verification.degenerate_height);
      q.field("degenerate_area", d.map.verification.degenerate_area);
      q.field("max_conformal_p99", d.map.verification.max_conformal_p99);
      // Fields added after models were first written carry their LEGACY value (how those models' descriptors were
      // computed) for files that lack them: the old verification refused distorted maps, the old operator was the
      // extrinsic cotan Laplacian, the old chain had no time budget.
      q.added(2, "strict_conformal_bound", d.map.verification.strict_conformal_bound, true);
    });
    m.added_group(2, "laplacian", [&](Visitor& l) {
      l.field("kind", d.map.laplacian.kind);
      l.field("mollify_delta", d.map.laplacian.mollify_delta);
      l.field("max_flips_per_edge", d.map.laplacian.max_flips_per_edge);
    }, d.map.laplacian, geometry::IntrinsicOptions{geometry::LaplacianKind::Extrinsic});
    m.added(2, "flow_budget_seconds", d.map.flow_budget_seconds, 0.0);
    m.added(3, "chain_budget_seconds", d.map.chain_budget_seconds, 0.0);
    m.added(3, "linear_reserve_seconds", d.map.linear_reserve_seconds, 0.0);
    // Off by default and measured harmful; at 0 its check was the chain budget's own (removed 2026-12-02).
    m.retired("min_fallback_flow_seconds", 2, 0.0);
    // The area-aware correction after the map; files of version 1 had none (the conformal map).
    m.added_group(2, "area_correction", [&](Visitor& a) {
      auto& o = d.map.area_correction;
      a.field("method", o.method);
      a.field("max_iterations", o.max_iterations);
      a.field("tolerance", o.tolerance);
      a.field("plateau", o.plateau);
      a.field("plateau_steps", o.plateau_steps);
      a.field("max_energy_rise", o.max_energy_rise);
      a.field("step", o.step);
      a.field("max_step", o.max_step);
      a.field("max_halvings", o.max_halvings);
      a.field("budget_seconds", o.budget_seconds);
    }, d.map.area_correction, AreaCorrectionOptions{});
    // The canonical map (canonical_map.hpp); older files computed the descriptor on the chain's own map.
    m.added_group(5, "canonical", [&](Visitor& c) {
      auto& o = d.map.canonical;
      c.field("method", o.method);
      c.field("energy", o.energy.kind);
      c.field("area_weight", o.energy.area_weight);
      c.field("mollify_delta", o.mollify_delta);
      c.field("max_iterations", o.max_iterations);
      c.field("tolerance", o.tolerance);
      c.field("absolute_tolerance", o.absolute_tolerance);
      c.field("max_halvings", o.max_halvings);
      c.field("budget_seconds", o.budget_seconds);
      c.field("scaled_damping", o.scaled_damping);
      c.field("extrapolate", o.extrapolate);
    }, d.map.canonical, CanonicalMapOptions{});  // legacy: method None (the default)
  });
  v.group("sh", [&](Visitor& s) {
    s.field("lmax", d.sh.lmax);
    s.field("regularization", d.sh.regularization);
    s.field("weighting", d.sh.weighting);
    s.field("solver", d.sh.solver);
    s.field("band_size", d.sh.band_size);
    s.field("gram", d.sh.gram);
    s.added(5, "sampling", d.sh.sampling, FitSampling::Vertices);  // older files fitted at the vertices
  });
  v.group("features", [&](Visitor& f) {
    f.field("family", d.features.family);
    f.field("l_min", d.features.l_min);
    f.field("l_max", d.features.l_max);
    f.field("scale", d.features.scale);
    f.field("log", d.features.log_transform);
    f.field("global_scale_free", d.features.global_scale_free);
    f.added(4, "spectrum_count", d.features.spectrum_count, 0);
    // The column names feature_names(features), written for readers of the file and checked on load.
    f.derived("names");
  });
  v.field("off_recipe", d.off_recipe);
}

}  // namespace wish
