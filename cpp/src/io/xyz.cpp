// XYZ point files: "x y z" or "x y z nx ny nz" per line.
#include <meshsmith/io/formats.h>
#include <meshsmith/io/parsing.h>

namespace meshsmith::io {

PointCloud parse_xyz(const std::string& path, std::string_view text) {
  LineReader lines(path, text);
  std::vector<double> values;
  std::string_view line, token;
  int columns = 0;
  while (lines.next_content(line)) {
    Tokens tokens(line);
    int count = 0;
    double value;
    while (tokens.next(token)) {
      if (!parse_double(token, value))
        lines.fail(quoted(token) + " is not a finite number");
      if (++count > 6) lines.fail("more than 6 values on a line (x y z [nx ny nz])");
      values.push_back(value);
    }
    if (columns == 0) {
      if (count != 3 && count != 6)
        lines.fail(std::to_string(count) + " values on a line (3 for x y z, 6 with normals)");
      columns = count;
    } else if (count != columns) {
      lines.fail(std::to_string(count) + " values on a line where the first line has " +
                 std::to_string(columns));
    }
  }
  if (columns == 0) throw InputError(path + ": no points in the file");
  const auto rows = static_cast<Eigen::Index>(values.size() / columns);
  PointCloud points;
  points.P.resize(rows, 3);
  if (columns == 6) points.N.resize(rows, 3);
  for (Eigen::Index i = 0; i < rows; ++i)
    for (int c = 0; c < 3; ++c) {
      points.P(i, c) = values[i * columns + c];
      if (columns == 6) points.N(i, c) = values[i * columns + 3 + c];
    }
  return points;
}

std::string format_xyz(const PointCloud& points) {
  OutputBuffer out;
  const bool normals = points.N.rows() > 0;
  out.reserve(static_cast<std::size_t>(points.P.rows()) * (normals ? 120 : 60));
  for (Eigen::Index i = 0; i < points.P.rows(); ++i) {
    for (int c = 0; c < (normals ? 6 : 3); ++c) {
      if (c > 0) out.character(' ');
      out.number(c < 3 ? points.P(i, c) : points.N(i, c - 3));
    }
    out.character('\n');
  }
  return out.take();
}

}  // namespace meshsmith::io
