#pragma once
// Removing the handles of one voxel object, as brain-imaging tools make a cortical surface genus 0: every handle is
// either cut (voxels taken out of the object where it is thinnest) or filled (background voxels added where the
// tunnel through it is narrowest), whichever changes less volume (Wood, Hoppe, Desbrun & Schröder 2004, "Removing
// excess topology from isosurfaces"; Ségonne, Pacheco & Fischl 2007, FreeSurfer's topology correction).
//
// How (the voxel analogue of Ségonne's two growths; voxel_topology.hpp for the simple-point test):
//   cut:  a set grown inside the object from its deepest voxel, adding only simple points, deepest first (squared
//         Euclidean distance to the background, physical units). It stays a topological ball; the object voxels it
//         cannot take without closing a loop are the cuts, and deepest-first leaves them where the handles are
//         thinnest.
//   fill: the background grown inward from the grid's border the same way, farthest from the object first; the
//         background voxels it cannot take are the plugs of the tunnels, left where the tunnels are narrowest.
// Each connected group (14-neighbourhood) of cut voxels severs one handle and each group of plug voxels fills one
// tunnel. Per handle: the groups are tried smallest first, each kept when it lowers the genus and leaves one
// component without cavities; the result is compared with cutting every handle and with filling every tunnel, and
// the one that changes the fewest voxels (removed + added) is chosen. Cutting alone and filling alone always give
// genus 0 (the grown set, or the complement of the grown background, is a ball), so a repair always exists; the
// caller decides whether its volume change is acceptable.
// Preconditions: the object is one 14-connected component without cavities, and the grid's border layer is
// background (object_surface.cpp's padded box). Cost: a few passes over the grid per group tried.

#include <cstdint>
#include <string>

#include "core/volume/binary_volume.hpp"

namespace wish::volume {

// What a repair changed (kept with the object's figures; the repaired voxels themselves are TopologyRepair::result).
struct TopologyRepairFigures {
  int genus_before = 0;             // handles of the object before the repair
  std::int64_t voxels_before = 0;   // object voxels before
  std::int64_t removed = 0, added = 0;  // by the chosen repair
  int cuts = 0, fills = 0;          // groups of voxels cut (handles severed) / added (tunnels filled)
  std::int64_t cut_every_handle = 0, fill_every_tunnel = 0;  // voxels changed by the two pure repairs (compared)
  // Voxels changed over voxels before: the repair's "volume change".
  double volume_change() const {
    return voxels_before > 0 ? static_cast<double>(removed + added) / static_cast<double>(voxels_before) : 0;
  }
  // "cut" | "fill" | "cut_and_fill" | "none"
  const char* method() const;
  // "cut 2 handles (-37 voxels), filled 1 tunnel (+12 voxels): genus 3 -> 0, volume change 0.41 %"
  std::string describe() const;
};

struct TopologyRepair {
  TopologyRepairFigures figures;
  BinaryVolume result;  // the object after the repair: one component, genus 0, no cavities
};

TopologyRepair remove_handles(const BinaryVolume& object);

}  // namespace wish::volume
