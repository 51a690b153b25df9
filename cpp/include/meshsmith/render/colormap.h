#pragma once
/// \file colormap.h
/// The colormaps of the render chapter: small tables of 17 sRGB control points, linearly
/// interpolated (viridis and magma, perceptually uniform; coolwarm, diverging, after Moreland).
#include <Eigen/Core>

#include <string>
#include <vector>

namespace meshsmith::render {

enum class Colormap { viridis, magma, coolwarm };

/// The colormap called `name` ("viridis", "magma", "coolwarm").
/// \throw InputError for any other name (the message lists the known ones).
Colormap colormap_from_name(const std::string& name);

/// Names of all colormaps, in the order of the enum.
std::vector<std::string> colormap_names();

/// True for colormaps meant for signed data centred on zero (coolwarm).
bool colormap_is_diverging(Colormap colormap);

/// sRGB colour in [0, 1]^3 of the colormap at t (clamped to [0, 1]; NaN gives the t = 0 end).
Eigen::Vector3d colormap_color(Colormap colormap, double t);

}  // namespace meshsmith::render
