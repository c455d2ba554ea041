// loadWorld, parseWorld and readSdfModel: libsdformat reads the SDF in a child process, which sends the
// WorldSpec back as bytes (world_spec.h says why).
#include <cstring>
#include <map>
#include <stdexcept>
#include <type_traits>

#include "bullet_sim/description/world_spec.h"
#include "description/child_process.h"

namespace bullet_sim {

namespace {

constexpr size_t kWorldParseMemory = size_t{8} << 30;  // [bytes] beyond this process's: 3,000 distinct models

// What crosses from the child, field by field: one list per type serves the writer and the reader, so the
// two cannot disagree. A Shape's mesh goes once, however many shapes share it.
template <class A>
void fields(A& a, Shape& s) {
  a(s.type, s.box_size, s.radius, s.length, s.plane_normal, s.mesh_path, s.mesh_scale);
}
template <class A>
void fields(A& a, Collision& c) {
  a(c.origin, c.shape, c.name);
}
template <class A>
void fields(A& a, Visual& v) {
  a(v.origin, v.shape, v.rgba, v.material);
}
template <class A>
void fields(A& a, InertialSpec& i) {
  a(i.mass, i.com, i.inertia);
}
template <class A>
void fields(A& a, SurfaceSpec& s) {
  a(s.mu1, s.mu2, s.kp, s.kd);
}
template <class A>
void fields(A& a, WorldLinkSpec& l) {
  a(l.name, l.pose, l.collisions, l.inertial, l.gravity, l.self_collide, l.surface, l.collision_indices,
    l.visual_indices);
}
template <class A>
void fields(A& a, WorldJointSpec& j) {
  a(j.name, j.type, j.parent, j.child, j.pose, j.axis, j.lower, j.upper, j.effort, j.velocity, j.damping,
    j.friction);
}
template <class A>
void fields(A& a, TagNode& t) {
  a(t.name, t.attributes, t.text, t.children, t.line);
}
template <class A>
void fields(A& a, SensorDeclaration& s) {
  a(s.name, s.type, s.link, s.pose, s.update_rate);
}
template <class A>
void fields(A& a, PluginElement& p) {
  a(p.plugin, p.sensor, p.sensor_tags, p.where);
}
template <class A>
void fields(A& a, WorldModelSpec& m) {
  a(m.name, m.pose, m.is_static, m.collisions, m.visuals, m.links, m.joints, m.plugins);
}
template <class A>
void fields(A& a, SphericalCoordinates& c) {
  a(c.latitude, c.longitude, c.elevation, c.heading);
}
template <class A>
void fields(A& a, WorldSpec& w) {
  a(w.source, w.name, w.gravity, w.max_step_size, w.real_time_factor, w.real_time_update_rate, w.models,
    w.spherical_coordinates);
}

template <class T>
constexpr bool kPlain = std::is_arithmetic_v<T> || std::is_enum_v<T>;

class Writer {
 public:
  template <class... T>
  void operator()(const T&... values) {
    (put(values), ...);
  }
  std::string take() { return std::move(bytes_); }

 private:
  template <class T>
  void put(const T& value) {
    if constexpr (kPlain<T>) {
      bytes_.append(reinterpret_cast<const char*>(&value), sizeof(T));
    } else {
      fields(*this, const_cast<T&>(value));  // fields() only reads here
    }
  }
  template <class T, int R, int C, int O, int MR, int MC>
  void put(const Eigen::Matrix<T, R, C, O, MR, MC>& matrix) {
    for (Eigen::Index i = 0; i < matrix.size(); ++i) put(matrix.data()[i]);
  }
  void put(const Eigen::Isometry3d& pose) { put(Eigen::Matrix<double, 3, 4>(pose.matrix().topRows<3>())); }
  void put(const std::string& text) {
    put<uint64_t>(text.size());
    bytes_ += text;
  }
  template <class T>
  void put(const std::optional<T>& value) {
    put(value.has_value());
    if (value) put(*value);
  }
  template <class T>
  void put(const std::vector<T>& values) {
    put<uint64_t>(values.size());
    for (const T& value : values) put(value);
  }
  void put(const std::map<std::string, std::string>& values) {
    put<uint64_t>(values.size());
    for (const auto& [key, value] : values) (*this)(key, value);
  }
  void put(const Shape& shape) {
    fields(*this, const_cast<Shape&>(shape));
    if (!shape.mesh) {
      put<uint64_t>(kNoMesh);
      return;
    }
    const auto [index, is_new] = meshes_.emplace(shape.mesh.get(), meshes_.size());
    put<uint64_t>(index->second);
    if (is_new) (*this)(shape.mesh->vertices, shape.mesh->triangles);
  }
  void put(const std::array<int, 3>& triangle) { (*this)(triangle[0], triangle[1], triangle[2]); }

  std::string bytes_;
  std::map<const TriangleMesh*, size_t> meshes_;

 public:
  static constexpr uint64_t kNoMesh = ~uint64_t{0};
};

/// Reads what Writer wrote; throws std::runtime_error when the bytes run out.
class Reader {
 public:
  explicit Reader(const std::string& bytes) : bytes_(bytes) {}
  template <class... T>
  void operator()(T&... values) {
    (get(values), ...);
  }

 private:
  template <class T>
  void get(T& value) {
    if constexpr (kPlain<T>) {
      std::memcpy(static_cast<void*>(&value), take(sizeof(T)), sizeof(T));
    } else {
      fields(*this, value);
    }
  }
  template <class T, int R, int C, int O, int MR, int MC>
  void get(Eigen::Matrix<T, R, C, O, MR, MC>& matrix) {
    for (Eigen::Index i = 0; i < matrix.size(); ++i) get(matrix.data()[i]);
  }
  void get(Eigen::Isometry3d& pose) {
    Eigen::Matrix<double, 3, 4> top;
    get(top);
    pose.matrix().setIdentity();
    pose.matrix().topRows<3>() = top;
  }
  void get(std::string& text) {
    const size_t size = count();
    text.assign(take(size), size);
  }
  template <class T>
  void get(std::optional<T>& value) {
    bool has = false;
    get(has);
    value.reset();
    if (has) get(value.emplace());
  }
  template <class T>
  void get(std::vector<T>& values) {
    values.resize(count());
    for (T& value : values) get(value);
  }
  void get(std::map<std::string, std::string>& values) {
    for (size_t n = count(); n > 0; --n) {
      std::string key, value;
      (*this)(key, value);
      values[key] = value;
    }
  }
  void get(Shape& shape) {
    fields(*this, shape);
    uint64_t index = 0;
    get(index);
    if (index == Writer::kNoMesh) return;
    if (index < meshes_.size()) {
      shape.mesh = meshes_[index];
      return;
    }
    auto mesh = std::make_shared<TriangleMesh>();
    (*this)(mesh->vertices, mesh->triangles);
    meshes_.push_back(mesh);
    shape.mesh = mesh;
  }
  void get(std::array<int, 3>& triangle) { (*this)(triangle[0], triangle[1], triangle[2]); }

  /// A count, no larger than the bytes left (each item takes one at least).
  size_t count() {
    uint64_t size = 0;
    get(size);
    if (size > bytes_.size() - at_) throw std::runtime_error("the world's bytes ended early");
    return size;
  }
  const char* take(size_t size) {
    if (size > bytes_.size() - at_) throw std::runtime_error("the world's bytes ended early");
    at_ += size;
    return bytes_.data() + at_ - size;
  }

  const std::string& bytes_;
  size_t at_ = 0;
  std::vector<std::shared_ptr<const TriangleMesh>> meshes_;
};

/// The child's answer: the warnings, then the world or the problems.
std::string encode(const WorldSpec* world, const std::vector<std::string>& problems,
                   const std::vector<std::string>& warnings) {
  Writer out;
  out(warnings, world != nullptr);
  if (world) {
    out(*world);
  } else {
    out(problems);
  }
  return out.take();
}

WorldSpec decode(const std::string& bytes, const std::string& source, std::vector<std::string>* warnings) {
  Reader in(bytes);
  std::vector<std::string> said;
  bool read = false;
  in(said, read);
  if (warnings) warnings->insert(warnings->end(), said.begin(), said.end());
  if (!read) {
    std::vector<std::string> problems;
    in(problems);
    throw SpecError(source, problems);
  }
  WorldSpec world;
  in(world);
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
      throw SpecError(source, {"reading the SDF failed: " + outcome.why});
    case ChildOutcome::Ending::kCrashed:
      throw SpecError(source, {"libsdformat crashed reading the SDF, with " + outcome.why +
                               ": the file is corrupt, or sdformat cannot read it; check it with gz sdf -k"});
    case ChildOutcome::Ending::kTimedOut:
      throw SpecError(source, {"reading the SDF took longer than " +
                               std::to_string(static_cast<int>(limits.world_load_seconds)) +
                               " s (world_load_seconds): is it that large?"});
    case ChildOutcome::Ending::kNotRun:
      break;
  }
  throw SpecError(source, {"cannot read the SDF: " + outcome.why});
}

}  // namespace

WorldSpec loadWorld(const std::string& path, const PackageResolver& resolver,
                    std::vector<std::string>* warnings, const WorldOptions& options) {
  return loadInChild(
      path, [&](std::vector<std::string>* said) { return loadWorldHere(path, resolver, said, options); },
      warnings, options.limits);
}

WorldSpec parseWorld(const std::string& sdf_text, const std::string& source, const PackageResolver& resolver,
                     std::vector<std::string>* warnings, const WorldOptions& options) {
  return loadInChild(
      source,
      [&](std::vector<std::string>* said) {
        return parseWorldHere(sdf_text, source, resolver, said, options);
      },
      warnings, options.limits);
}

WorldModelSpec readSdfModel(const std::string& sdf_text, const std::string& source,
                            const PackageResolver& resolver, std::vector<std::string>* warnings,
                            const Limits& limits) {
  WorldSpec holder = loadInChild(
      source,
      [&](std::vector<std::string>* said) {
        WorldSpec world;
        world.models.push_back(readSdfModelHere(sdf_text, source, resolver, said, limits));
        return world;
      },
      warnings, limits);
  return std::move(holder.models.front());
}

}  // namespace bullet_sim
