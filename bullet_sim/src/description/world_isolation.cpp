// loadWorld and parseWorld: libsdformat reads the world in a child process, which sends the WorldSpec back as
// bytes (world_spec.h says why).
#include <cstring>
#include <map>
#include <stdexcept>

#include "bullet_sim/description/world_spec.h"
#include "description/child_process.h"

namespace bullet_sim {

namespace {

constexpr size_t kWorldParseMemory = size_t{8} << 30;  // [bytes] beyond this process's: 3,000 distinct models

/// Appends plain values to bytes: numbers, enums, std::arrays of them and fixed-size Eigen matrices.
class Writer {
 public:
  template <class T>
  void put(const T& value) {
    bytes_.append(reinterpret_cast<const char*>(&value), sizeof(T));
  }
  void put(const std::string& text) {
    put<uint64_t>(text.size());
    bytes_ += text;
  }
  void put(const Eigen::Isometry3d& pose) { put(Eigen::Matrix<double, 3, 4>(pose.matrix().topRows<3>())); }
  std::string take() { return std::move(bytes_); }

 private:
  std::string bytes_;
};

/// Reads what Writer wrote; throws std::runtime_error when the bytes run out.
class Reader {
 public:
  explicit Reader(const std::string& bytes) : bytes_(bytes) {}
  template <class T>
  T get() {
    T value;
    std::memcpy(static_cast<void*>(&value), take(sizeof(T)), sizeof(T));
    return value;
  }
  std::string text() {
    const auto size = get<uint64_t>();
    return std::string(take(size), size);
  }
  Eigen::Isometry3d pose() {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.matrix().topRows<3>() = get<Eigen::Matrix<double, 3, 4>>();
    return pose;
  }

 private:
  const char* take(size_t size) {
    if (size > bytes_.size() - at_) throw std::runtime_error("the world's bytes ended early");
    at_ += size;
    return bytes_.data() + at_ - size;
  }
  const std::string& bytes_;
  size_t at_ = 0;
};

/// Shapes, each mesh once: shapes name their mesh by its index.
class ShapeCodec {
 public:
  void put(Writer& out, const Shape& shape) {
    out.put(shape.type);
    out.put(shape.box_size);
    out.put(shape.radius);
    out.put(shape.length);
    out.put(shape.plane_normal);
    out.put(shape.mesh_path);
    out.put(shape.mesh_scale);
    const auto [index, is_new] = indices_.emplace(shape.mesh.get(), indices_.size());
    out.put<uint64_t>(shape.mesh ? index->second : kNoMesh);
    if (!shape.mesh || !is_new) return;
    out.put<uint64_t>(shape.mesh->vertices.size());
    for (const auto& vertex : shape.mesh->vertices) out.put(vertex);
    out.put<uint64_t>(shape.mesh->triangles.size());
    for (const auto& triangle : shape.mesh->triangles) out.put(triangle);
  }

  Shape get(Reader& in) {
    Shape shape;
    shape.type = in.get<Shape::Type>();
    shape.box_size = in.get<Eigen::Vector3d>();
    shape.radius = in.get<double>();
    shape.length = in.get<double>();
    shape.plane_normal = in.get<Eigen::Vector3d>();
    shape.mesh_path = in.text();
    shape.mesh_scale = in.get<Eigen::Vector3d>();
    const auto index = in.get<uint64_t>();
    if (index == kNoMesh) return shape;
    if (index < meshes_.size()) {
      shape.mesh = meshes_[index];
      return shape;
    }
    auto mesh = std::make_shared<TriangleMesh>();
    mesh->vertices.resize(in.get<uint64_t>());
    for (auto& vertex : mesh->vertices) vertex = in.get<Eigen::Vector3d>();
    mesh->triangles.resize(in.get<uint64_t>());
    for (auto& triangle : mesh->triangles) triangle = in.get<std::array<int, 3>>();
    meshes_.push_back(mesh);
    shape.mesh = mesh;
    return shape;
  }

 private:
  static constexpr uint64_t kNoMesh = ~uint64_t{0};
  std::map<const TriangleMesh*, size_t> indices_;
  std::vector<std::shared_ptr<const TriangleMesh>> meshes_;
};

void putModel(Writer& out, ShapeCodec& shapes, const WorldModelSpec& model) {
  out.put(model.name);
  out.put(model.pose);
  out.put(model.is_static);
  out.put<uint64_t>(model.collisions.size());
  for (const Collision& collision : model.collisions) {
    out.put(collision.origin);
    shapes.put(out, collision.shape);
  }
  out.put<uint64_t>(model.visuals.size());
  for (const Visual& visual : model.visuals) {
    out.put(visual.origin);
    shapes.put(out, visual.shape);
    out.put(visual.rgba);
    out.put(visual.material);
  }
}

WorldModelSpec getModel(Reader& in, ShapeCodec& shapes) {
  WorldModelSpec model;
  model.name = in.text();
  model.pose = in.pose();
  model.is_static = in.get<bool>();
  model.collisions.resize(in.get<uint64_t>());
  for (Collision& collision : model.collisions) {
    collision.origin = in.pose();
    collision.shape = shapes.get(in);
  }
  model.visuals.resize(in.get<uint64_t>());
  for (Visual& visual : model.visuals) {
    visual.origin = in.pose();
    visual.shape = shapes.get(in);
    visual.rgba = in.get<Eigen::Vector4d>();
    visual.material = in.text();
  }
  return model;
}

void putTexts(Writer& out, const std::vector<std::string>& texts) {
  out.put<uint64_t>(texts.size());
  for (const auto& text : texts) out.put(text);
}

std::vector<std::string> getTexts(Reader& in) {
  std::vector<std::string> texts(in.get<uint64_t>());
  for (auto& text : texts) text = in.text();
  return texts;
}

/// The child's answer: the warnings, then the world or the problems.
std::string encode(const WorldSpec* world, const std::vector<std::string>& problems,
                   const std::vector<std::string>& warnings) {
  Writer out;
  putTexts(out, warnings);
  out.put(world != nullptr);
  if (!world) {
    putTexts(out, problems);
    return out.take();
  }
  out.put(world->source);
  out.put(world->name);
  out.put(world->gravity);
  out.put(world->max_step_size);
  out.put(world->real_time_factor);
  out.put<uint64_t>(world->models.size());
  ShapeCodec shapes;
  for (const auto& model : world->models) putModel(out, shapes, model);
  return out.take();
}

WorldSpec decode(const std::string& bytes, const std::string& source, std::vector<std::string>* warnings) {
  Reader in(bytes);
  const std::vector<std::string> said = getTexts(in);
  if (warnings) warnings->insert(warnings->end(), said.begin(), said.end());
  if (!in.get<bool>()) throw SpecError(source, getTexts(in));
  WorldSpec world;
  world.source = in.text();
  world.name = in.text();
  world.gravity = in.get<Eigen::Vector3d>();
  world.max_step_size = in.get<double>();
  world.real_time_factor = in.get<double>();
  world.models.resize(in.get<uint64_t>());
  ShapeCodec shapes;
  for (auto& model : world.models) model = getModel(in, shapes);
  return world;
}

/// Runs `load` in a child process, and hands back what it read or the problems it found.
template <class Load>
WorldSpec loadInChild(const std::string& source, const Load& load, std::vector<std::string>* warnings,
                      const Limits& limits) {
  const ChildOutcome outcome = runInChild(
      [&] {
        std::vector<std::string> said;
        try {
          const WorldSpec world = load(&said);
          return encode(&world, {}, said);
        } catch (const SpecError& e) {
          return encode(nullptr, e.problems(), said);
        }
      },
      kWorldParseMemory, limits.world_load_seconds);
  switch (outcome.ending) {
    case ChildOutcome::Ending::kReturned:
      return decode(outcome.output, source, warnings);
    case ChildOutcome::Ending::kThrew:
      throw SpecError(source, {"reading the world failed: " + outcome.why});
    case ChildOutcome::Ending::kCrashed:
      throw SpecError(source, {"libsdformat crashed reading the world, with " + outcome.why +
                               ": the file is corrupt, or sdformat cannot read it; check it with gz sdf -k"});
    case ChildOutcome::Ending::kTimedOut:
      throw SpecError(source, {"reading the world took longer than " +
                               std::to_string(static_cast<int>(limits.world_load_seconds)) +
                               " s (world_load_seconds): is it that large?"});
    case ChildOutcome::Ending::kNotRun:
      break;
  }
  throw SpecError(source, {"cannot read the world: " + outcome.why});
}

}  // namespace

WorldSpec loadWorld(const std::string& path, const PackageResolver& resolver,
                    std::vector<std::string>* warnings, const Limits& limits) {
  return loadInChild(
      path, [&](std::vector<std::string>* said) { return loadWorldHere(path, resolver, said, limits); },
      warnings, limits);
}

WorldSpec parseWorld(const std::string& sdf_text, const std::string& source, const PackageResolver& resolver,
                     std::vector<std::string>* warnings, const Limits& limits) {
  return loadInChild(
      source,
      [&](std::vector<std::string>* said) {
        return parseWorldHere(sdf_text, source, resolver, said, limits);
      },
      warnings, limits);
}

}  // namespace bullet_sim
