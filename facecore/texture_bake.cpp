#include "facecore/texture_bake.hpp"

#include <algorithm>
#include <cmath>

namespace rostro {

Texture bake_texture(const FaceModel& model, const std::vector<int>& triangles, int width,
                     int height, const std::function<Eigen::Vector3f(const TexelPoint&)>& colour) {
  Texture texture;
  texture.width = width;
  texture.height = height;
  const auto texels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  texture.rgb.assign(3 * texels, 0);
  std::vector<bool> covered(texels, false);
  auto put = [&](int x, int row, const Eigen::Vector3f& c) {
    x = (x % width + width) % width;
    const std::size_t i = static_cast<std::size_t>(row) * static_cast<std::size_t>(width) +
                          static_cast<std::size_t>(x);
    for (int k = 0; k < 3; ++k)
      texture.rgb[3 * i + static_cast<std::size_t>(k)] =
          static_cast<std::uint8_t>(std::lround(255.0f * std::clamp(c[k], 0.0f, 1.0f)));
    covered[i] = true;
  };
  for (int t : triangles) {
    const Eigen::Vector3i& tri = model.triangles[static_cast<std::size_t>(t)];
    Eigen::Vector2d uv[3];
    Eigen::Vector3d p[3];
    for (int k = 0; k < 3; ++k) {
      const auto v = static_cast<std::size_t>(tri[k]);
      uv[k] = model.texcoords[v].cast<double>();
      p[k] = model.positions[v].cast<double>();
    }
    const double u_max = std::max({uv[0].x(), uv[1].x(), uv[2].x()});
    for (auto& c : uv)
      if (u_max - c.x() > 0.5) c.x() += 1.0;  // across the seam: the short way round
    // Texel space: x along u, rows down from v = 1; texel centres at half-integers.
    Eigen::Vector2d q[3];
    for (int k = 0; k < 3; ++k) q[k] = {uv[k].x() * width, (1.0 - uv[k].y()) * height};
    const double area =
        (q[1] - q[0]).x() * (q[2] - q[0]).y() - (q[1] - q[0]).y() * (q[2] - q[0]).x();
    if (std::abs(area) < 1e-12) continue;
    const int x0 = static_cast<int>(std::floor(std::min({q[0].x(), q[1].x(), q[2].x()})));
    const int x1 = static_cast<int>(std::ceil(std::max({q[0].x(), q[1].x(), q[2].x()})));
    const int y0 =
        std::max(0, static_cast<int>(std::floor(std::min({q[0].y(), q[1].y(), q[2].y()}))));
    const int y1 =
        std::min(height - 1, static_cast<int>(std::ceil(std::max({q[0].y(), q[1].y(), q[2].y()}))));
    for (int row = y0; row <= y1; ++row)
      for (int x = x0; x <= x1; ++x) {
        const Eigen::Vector2d c(x + 0.5, row + 0.5);
        auto edge = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
          return ((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x()) / area;
        };
        const double w0 = edge(q[1], q[2]), w1 = edge(q[2], q[0]), w2 = edge(q[0], q[1]);
        constexpr double kEdge = -1e-9;  // texels on a shared edge are painted by both
        if (w0 < kEdge || w1 < kEdge || w2 < kEdge) continue;
        TexelPoint point{w0 * p[0] + w1 * p[1] + w2 * p[2], w0 * uv[0] + w1 * uv[1] + w2 * uv[2]};
        put(x, row, colour(point));
      }
  }
  // Fill what no triangle covers from the nearest covered texel: along each row, then each
  // column (rows with nothing covered take the column's fill).
  auto fill = [&](int count, int length, auto index) {
    for (int line = 0; line < count; ++line) {
      int last = -1;
      std::vector<int> nearest(static_cast<std::size_t>(length), -1);
      for (int i = 0; i < length; ++i)
        if (covered[index(line, i)])
          last = i;
        else
          nearest[static_cast<std::size_t>(i)] = last;
      last = -1;
      for (int i = length - 1; i >= 0; --i) {
        if (covered[index(line, i)]) {
          last = i;
          continue;
        }
        int& n = nearest[static_cast<std::size_t>(i)];
        if (last >= 0 && (n < 0 || last - i < i - n)) n = last;
      }
      for (int i = 0; i < length; ++i) {
        const int n = nearest[static_cast<std::size_t>(i)];
        if (covered[index(line, i)] || n < 0) continue;
        std::copy_n(texture.rgb.begin() + static_cast<std::ptrdiff_t>(3 * index(line, n)), 3,
                    texture.rgb.begin() + static_cast<std::ptrdiff_t>(3 * index(line, i)));
      }
      for (int i = 0; i < length; ++i)
        if (nearest[static_cast<std::size_t>(i)] >= 0) covered[index(line, i)] = true;
    }
  };
  const auto w = static_cast<std::size_t>(width);
  fill(height, width, [&](int row, int x) {
    return static_cast<std::size_t>(row) * w + static_cast<std::size_t>(x);
  });
  fill(width, height, [&](int x, int row) {
    return static_cast<std::size_t>(row) * w + static_cast<std::size_t>(x);
  });
  return texture;
}

Eigen::Vector3f sample_texture(const Texture& texture, const Eigen::Vector2f& uv) {
  const double u = uv.x(), v = uv.y();
  const double x = (u - std::floor(u)) * texture.width - 0.5;
  const double y = std::clamp((1.0 - v) * texture.height - 0.5, 0.0, texture.height - 1.0);
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const double fx = x - x0, fy = y - y0;
  auto texel = [&](int tx, int ty) {
    tx = (tx % texture.width + texture.width) % texture.width;
    ty = std::clamp(ty, 0, texture.height - 1);
    const std::size_t i =
        3 * (static_cast<std::size_t>(ty) * static_cast<std::size_t>(texture.width) +
             static_cast<std::size_t>(tx));
    Eigen::Vector3d c;
    for (int k = 0; k < 3; ++k) c[k] = texture.rgb[i + static_cast<std::size_t>(k)] / 255.0;
    return c;
  };
  const Eigen::Vector3d c = (1 - fy) * ((1 - fx) * texel(x0, y0) + fx * texel(x0 + 1, y0)) +
                            fy * ((1 - fx) * texel(x0, y0 + 1) + fx * texel(x0 + 1, y0 + 1));
  return c.cast<float>();
}

}  // namespace rostro
