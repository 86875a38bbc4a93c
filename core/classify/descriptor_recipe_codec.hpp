#pragma once
// Every field of DescriptorRecipe (spherical-map options, SH fit options, feature pipeline, off-recipe policy),
// listed ONCE in visit_recipe(), so that the model file writes all of them and reads all of them back: a model
// must reproduce the descriptor it was trained on exactly (classification.md: never silently mismatched). Adding a
// field to SphericalMapOptions, ShFitOptions or FeatureSpec means adding one line here (and, when it changes what
// old files mean, bumping DescriptorRecipe::kVersion); the round-trip test in tests/classify/model_file_test.cpp
// compares every field through operator==.
//
// A visitor provides: field(key, double&|int&|bool&), enumeration(key, E&), group(key, lambda) for nesting, and
// legacy_field(key, value&, legacy) / legacy_group(key, lambda, target&, legacy) for fields that older files lack.

#include "core/classify/descriptor_recipe.hpp"

namespace wish {

template <class Visitor, class Recipe>
void visit_recipe(Visitor& v, Recipe& d) {
  v.group("map", [&](Visitor& m) {
    m.enumeration("method", d.map.method);
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
      c.legacy_field("stall_patience", o.stall_patience, 1);
    });
    m.group("linear", [&](Visitor& l) {
      l.field("min_weight", d.map.linear.min_weight);
      l.field("always_clamp", d.map.linear.always_clamp);
    });
    m.enumeration("solver", d.map.solver);
    m.field("fallback", d.map.fallback);
    m.field("untangle", d.map.untangle);
    m.group("verification", [&](Visitor& q) {
      q.field("degenerate_height", d.map.verification.degenerate_height);
      q.field("degenerate_area", d.map.verification.degenerate_area);
      q.field("max_conformal_p99", d.map.verification.max_conformal_p99);
      // Fields added after models were first written carry their LEGACY value (how those models' descriptors were
      // computed) for files that lack them: the old verification refused distorted maps, the old operator was the
      // extrinsic cotan Laplacian, the old chain had no time budget.
      q.legacy_field("strict_conformal_bound", d.map.verification.strict_conformal_bound, true);
    });
    m.legacy_group("laplacian", [&](Visitor& l) {
      l.enumeration("kind", d.map.laplacian.kind);
      l.field("mollify_delta", d.map.laplacian.mollify_delta);
      l.field("max_flips_per_edge", d.map.laplacian.max_flips_per_edge);
    }, d.map.laplacian, geometry::IntrinsicOptions{geometry::LaplacianKind::Extrinsic});
    m.legacy_field("flow_budget_seconds", d.map.flow_budget_seconds, 0.0);
    m.legacy_field("chain_budget_seconds", d.map.chain_budget_seconds, 0.0);
    m.legacy_field("linear_reserve_seconds", d.map.linear_reserve_seconds, 0.0);
    // Recipe version 2: the area-aware correction after the map; files of version 1 had none (the conformal map).
    m.legacy_group("area_correction", [&](Visitor& a) {
      auto& o = d.map.area_correction;
      a.enumeration("method", o.method);
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
  });
  v.group("sh", [&](Visitor& s) {
    s.field("lmax", d.sh.lmax);
    s.field("regularization", d.sh.regularization);
    s.enumeration("weighting", d.sh.weighting);
    s.enumeration("solver", d.sh.solver);
    s.field("band_size", d.sh.band_size);
    s.enumeration("gram", d.sh.gram);
  });
  v.group("features", [&](Visitor& f) {
    f.enumeration("family", d.features.family);
    f.field("l_min", d.features.l_min);
    f.field("l_max", d.features.l_max);
    f.enumeration("scale", d.features.scale);
    f.field("log", d.features.log_transform);
    f.field("global_scale_free", d.features.global_scale_free);
  });
  v.enumeration("off_recipe", d.off_recipe);
}

}  // namespace wish
