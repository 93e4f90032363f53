// `rostro head`: generate the default head (mesh + face model description).

#include <cstdio>
#include <string>

#include "apps/commands.hpp"
#include "facecore/face_model.hpp"
#include "facecore/head_generator.hpp"

namespace rostro::app {

void add_head_commands(CLI::App& app) {
  auto* head = app.add_subcommand(
      "head",
      "Generate rostro's procedural head: <dir>/head.obj (texture coordinates, vertex colours), "
      "<dir>/head.png (the skin's texture) and <dir>/head.json (feature points, influence "
      "regions, rigid parts, the neck's turn weights)");
  head->footer(
      "The default head in data/head/ was made with the first example.\n\n"
      "Example:\n"
      "  rostro head -o data/head --vertices 5000\n"
      "  rostro head -o /tmp/bighead --vertices 200000");
  auto dir = std::make_shared<std::string>();
  auto vertices = std::make_shared<int>(5000);
  head->add_option("-o,--output", *dir, "Output folder (created if missing)")->required();
  head->add_option("--vertices", *vertices, "Approximate vertex count (at least 1500)")
      ->capture_default_str();
  head->callback([dir, vertices] {
    const FaceModel model = generate_head(HeadOptions{*vertices});
    save_face_model(model, *dir, "head");
    std::printf(
        "%s/head.obj, %s/head.png, %s/head.json: %zu vertices, %zu triangles, %zu feature "
        "points, %zu regions\n",
        dir->c_str(), dir->c_str(), dir->c_str(), model.positions.size(), model.triangles.size(),
        model.feature_points.size(), model.regions.size());
  });
}

}  // namespace rostro::app
