#pragma once
// The describer of a training set (core/training/dataset.hpp) that computes every sample as a DescriptorRecipe
// says: a mesh file gives one sample, a label volume one sample per kept object (core/pipeline/volume_pipeline.hpp).
// A sample whose map came from another method than the recipe's is a loss ("off_recipe") when the recipe's policy
// refuses that, else kept and flagged. Global descriptors are always computed (the feature family comparison
// needs them).

#include "core/classify/descriptor_recipe.hpp"
#include "core/pipeline/pipeline.hpp"
#include "core/pipeline/volume_pipeline.hpp"
#include "core/training/dataset.hpp"

namespace wish {

struct TrainingDescribeOptions {
  PipelineOptions base;   // reading and repair limits; map and fit come from the recipe
  VolumeOptions volume;   // for label volumes: voxel size, object filters, surface
};

// The file's bytes, or IoError("file_not_found") naming it.
std::string read_input_file(const std::string& path);

ItemDescriber recipe_describer(const DescriptorRecipe& recipe, const TrainingDescribeOptions& options = {});

}  // namespace wish
