// Colormap tables of the render chapter (17 evenly spaced sRGB control points each).
#include <meshsmith/core/errors.h>
#include <meshsmith/render/colormap.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace meshsmith::render {
namespace {

constexpr int kControlPoints = 17;
using Table = std::array<std::array<double, 3>, kControlPoints>;

constexpr Table kViridis{{
    {0.2670, 0.0049, 0.3294}, {0.2823, 0.0950, 0.4173}, {0.2788, 0.1755, 0.4834},
    {0.2590, 0.2515, 0.5247}, {0.2297, 0.3224, 0.5457}, {0.1994, 0.3876, 0.5546},
    {0.1727, 0.4488, 0.5579}, {0.1490, 0.5081, 0.5573}, {0.1276, 0.5669, 0.5506},
    {0.1206, 0.6258, 0.5335}, {0.1579, 0.6838, 0.5017}, {0.2461, 0.7389, 0.4520},
    {0.3692, 0.7889, 0.3829}, {0.5160, 0.8312, 0.2943}, {0.6785, 0.8637, 0.1895},
    {0.8456, 0.8873, 0.0997}, {0.9932, 0.9062, 0.1439}}};

constexpr Table kMagma{{
    {0.0015, 0.0005, 0.0139}, {0.0396, 0.0311, 0.1335}, {0.1131, 0.0655, 0.2768},
    {0.2117, 0.0620, 0.4186}, {0.3167, 0.0717, 0.4854}, {0.4147, 0.1104, 0.5047},
    {0.5128, 0.1482, 0.5076}, {0.6136, 0.1818, 0.4985}, {0.7164, 0.2150, 0.4753},
    {0.8169, 0.2559, 0.4365}, {0.9043, 0.3196, 0.3881}, {0.9609, 0.4183, 0.3596},
    {0.9867, 0.5356, 0.3822}, {0.9961, 0.6537, 0.4462}, {0.9969, 0.7696, 0.5349},
    {0.9924, 0.8843, 0.6401}, {0.9871, 0.9914, 0.7495}}};

constexpr Table kCoolwarm{{
    {0.2298, 0.2987, 0.7537}, {0.3042, 0.4069, 0.8453}, {0.3837, 0.5102, 0.9178},
    {0.4677, 0.6056, 0.9685}, {0.5543, 0.6901, 0.9955}, {0.6408, 0.7608, 0.9978},
    {0.7240, 0.8149, 0.9757}, {0.8006, 0.8504, 0.9300}, {0.8674, 0.8644, 0.8626},
    {0.9256, 0.8255, 0.7711}, {0.9595, 0.7670, 0.6741}, {0.9697, 0.6905, 0.5751},
    {0.9567, 0.5980, 0.4773}, {0.9214, 0.4914, 0.3834}, {0.8654, 0.3711, 0.2958},
    {0.7906, 0.2314, 0.2162}, {0.7057, 0.0156, 0.1502}}};

const Table& table_of(Colormap colormap) {
  switch (colormap) {
    case Colormap::magma: return kMagma;
    case Colormap::coolwarm: return kCoolwarm;
    case Colormap::viridis: break;
  }
  return kViridis;
}

}  // namespace

std::vector<std::string> colormap_names() { return {"viridis", "magma", "coolwarm"}; }

Colormap colormap_from_name(const std::string& name) {
  if (name == "viridis") return Colormap::viridis;
  if (name == "magma") return Colormap::magma;
  if (name == "coolwarm") return Colormap::coolwarm;
  throw InputError("unknown colormap '" + name + "': use viridis, magma or coolwarm");
}

bool colormap_is_diverging(Colormap colormap) { return colormap == Colormap::coolwarm; }

Eigen::Vector3d colormap_color(Colormap colormap, double t) {
  const Table& table = table_of(colormap);
  if (!(t > 0.0)) t = 0.0;  // also catches NaN
  if (t > 1.0) t = 1.0;
  const double position = t * (kControlPoints - 1);
  const int below = std::min(static_cast<int>(position), kControlPoints - 2);
  const double weight = position - below;
  Eigen::Vector3d color;
  for (int c = 0; c < 3; ++c)
    color[c] = (1.0 - weight) * table[below][c] + weight * table[below + 1][c];
  return color;
}

}  // namespace meshsmith::render
