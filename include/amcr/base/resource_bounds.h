// Upper bounds on the work and memory a recognizer may be asked for. Each is
// checked up front, before anything is allocated, and refused with an error
// that gives the figure asked for and the bound (docs/configuration.md, "Resource bounds").
//
// The documented use lies well inside: 60 V x 60 M x 70 prototypes is
// 252,000 M-particles (32 times below the bound), a 1280x720 frame is
// 0.92 Mpixel (36 times below), a memory of 1000 prototypes at 128 px is
// at most 1.8 GB of tables (half the bound).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace amcr
{
/// M-particles of all V-particles (V x M per prototype x prototypes of
/// non-zero prior weight), count. At kBytesPerMParticle each: 720 MB.
constexpr std::int64_t kMaxMParticles = 8'000'000;

/// Memory of one M-particle: its state and the resampling scratch copy, bytes.
constexpr std::int64_t kBytesPerMParticle = 90;

/// Pixels of one input image or one prototype image (width x height): 8K UHD,
/// 7680 x 4320.
constexpr std::int64_t kMaxImagePixels = 7680LL * 4320LL;

/// Size of one image file read from disk, bytes (512 MiB).
constexpr std::int64_t kMaxImageFileBytes = 512LL * 1024 * 1024;

/// Size of a parameter file, bytes (1 MiB; config/amcr.yaml has 7 kB).
constexpr std::int64_t kMaxParameterFileBytes = 1024 * 1024;

/// Memory of all prototype lookup tables together, bytes (4 GiB).
constexpr std::int64_t kMaxTableBytes = 4LL * 1024 * 1024 * 1024;

/// ParameterError when `v_particles` x `m_per_v` exceeds kMaxMParticles;
/// `what` says where the M-particles per V come from (for the message).
void checkParticleBound(std::int64_t v_particles, std::int64_t m_per_v, const std::string& what);

/// InputError when width x height exceeds kMaxImagePixels; `what` names the image.
void checkImageBound(std::int64_t width, std::int64_t height, const std::string& what);

/// A count of bytes for messages: "1.84 GB", "29.5 MB".
std::string formatBytes(double bytes);

/// A whole count for messages, also beyond 64 bits ("18446744065119617025").
std::string formatCount(double count);
}  // namespace amcr
