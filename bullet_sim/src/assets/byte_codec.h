// Values as bytes through a child process's pipe (child_process.h), and back: numbers, enums, strings,
// Eigen's fixed-size matrices and poses, std::optional, std::vector, std::array and std::map of them, shared
// objects (each sent once, shared again on arrival), and any struct with a `fields(archive, value)` function
// in namespace bullet_sim that lists its members: one list serves both ways, so writer and reader cannot
// disagree.
#pragma once

#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace bullet_sim {

template <class T>
constexpr bool kPlainBytes = std::is_arithmetic_v<T> || std::is_enum_v<T>;

class ByteWriter {
 public:
  template <class... T>
  void operator()(const T&... values) {
    (put(values), ...);
  }
  std::string take() { return std::move(bytes_); }

 private:
  template <class T>
  void put(const T& value) {
    if constexpr (kPlainBytes<T>) {
      bytes_.append(reinterpret_cast<const char*>(&value), sizeof(T));
    } else {
      fields(*this, const_cast<T&>(value));  // fields() only reads here
    }
  }
  template <class T, int R, int C, int O, int MR, int MC>
  void put(const Eigen::Matrix<T, R, C, O, MR, MC>& matrix) {
    bytes_.append(reinterpret_cast<const char*>(matrix.data()), sizeof(T) * R * C);
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
  template <class T, class A>
  void put(const std::vector<T, A>& values) {
    put<uint64_t>(values.size());
    if constexpr (kPlainBytes<T>) {
      bytes_.append(reinterpret_cast<const char*>(values.data()), sizeof(T) * values.size());
    } else {
      for (const T& value : values) put(value);
    }
  }
  template <class T, size_t N>
  void put(const std::array<T, N>& values) {
    for (const T& value : values) put(value);
  }
  template <class K, class V>
  void put(const std::map<K, V>& values) {
    put<uint64_t>(values.size());
    for (const auto& [key, value] : values) (*this)(key, value);
  }
  /// nullptr as 0, else the object's number from 1: in full the first time, by number after.
  template <class T>
  void put(const std::shared_ptr<const T>& shared) {
    if (!shared) {
      put<uint64_t>(0);
      return;
    }
    const auto [found, is_new] = shared_.emplace(shared.get(), shared_.size() + 1);
    put<uint64_t>(found->second);
    if (is_new) put(*shared);
  }

  std::string bytes_;
  std::map<const void*, uint64_t> shared_;
};

/// Reads what ByteWriter wrote; throws std::runtime_error when the bytes run out.
class ByteReader {
 public:
  explicit ByteReader(const std::string& bytes) : bytes_(bytes) {}
  template <class... T>
  void operator()(T&... values) {
    (get(values), ...);
  }

 private:
  template <class T>
  void get(T& value) {
    if constexpr (kPlainBytes<T>) {
      std::memcpy(static_cast<void*>(&value), take(sizeof(T)), sizeof(T));
    } else {
      fields(*this, value);
    }
  }
  template <class T, int R, int C, int O, int MR, int MC>
  void get(Eigen::Matrix<T, R, C, O, MR, MC>& matrix) {
    std::memcpy(static_cast<void*>(matrix.data()), take(sizeof(T) * R * C), sizeof(T) * R * C);
  }
  void get(Eigen::Isometry3d& pose) {
    Eigen::Matrix<double, 3, 4> top;
    get(top);
    pose.matrix().setIdentity();
    pose.matrix().topRows<3>() = top;
  }
  void get(std::string& text) {
    const size_t size = count(1);
    text.assign(take(size), size);
  }
  template <class T>
  void get(std::optional<T>& value) {
    bool has = false;
    get(has);
    value.reset();
    if (has) get(value.emplace());
  }
  template <class T, class A>
  void get(std::vector<T, A>& values) {
    values.resize(count(kPlainBytes<T> ? sizeof(T) : 1));
    if constexpr (kPlainBytes<T>) {
      std::memcpy(static_cast<void*>(values.data()), take(sizeof(T) * values.size()),
                  sizeof(T) * values.size());
    } else {
      for (T& value : values) get(value);
    }
  }
  template <class T, size_t N>
  void get(std::array<T, N>& values) {
    for (T& value : values) get(value);
  }
  template <class K, class V>
  void get(std::map<K, V>& values) {
    for (size_t n = count(1); n > 0; --n) {
      K key;
      V value;
      (*this)(key, value);
      values.emplace(std::move(key), std::move(value));
    }
  }
  template <class T>
  void get(std::shared_ptr<const T>& shared) {
    uint64_t number = 0;
    get(number);
    shared.reset();
    if (number == 0) return;
    if (number <= shared_.size()) {
      shared = std::static_pointer_cast<const T>(shared_[number - 1]);
      return;
    }
    if (number != shared_.size() + 1) throw std::runtime_error("the bytes name an object out of order");
    auto made = std::make_shared<T>();
    shared_.push_back(made);  // before its contents, which cannot name it
    get(*made);
    shared = made;
  }

  /// A count of items of at least `item_bytes` each, no more than the bytes left hold.
  size_t count(size_t item_bytes) {
    uint64_t size = 0;
    get(size);
    if (size > (bytes_.size() - at_) / item_bytes) throw std::runtime_error("the bytes ended early");
    return size;
  }
  const char* take(size_t size) {
    if (size > bytes_.size() - at_) throw std::runtime_error("the bytes ended early");
    at_ += size;
    return bytes_.data() + at_ - size;
  }

  const std::string& bytes_;
  size_t at_ = 0;
  std::vector<std::shared_ptr<const void>> shared_;
};

}  // namespace bullet_sim
