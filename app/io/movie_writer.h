#pragma once
/// \file movie_writer.h
/// RGB frames to an MP4 movie through FFmpeg's libraries (libavformat, libavcodec, libswscale),
/// and a probe that reads a movie's size, codec and frame count back. This header includes no
/// FFmpeg header. A build without the libraries (FF_HAVE_LIBAV undefined) keeps the API: create()
/// fails with a message that says so (movie_support() tells in advance).
///
/// Codec: H.264 (libx264, yuv420p, CRF 20) when libavcodec has it, else MPEG-4 part 2 (always
/// built into libavcodec). yuv420p needs even sizes: an odd width or height is padded by
/// repeating the last column/row.

#include <cstdint>
#include <memory>
#include <string>

namespace ff::io {

/// "" when MP4 output is available in this build, else why not.
std::string movie_support();

class MovieWriter {
 public:
  /// Opens `path` (.mp4) for frames of width x height pixels at `fps` frames per second.
  /// Returns nullptr and sets *error on failure (no encoder, unwritable path, bad size).
  static std::unique_ptr<MovieWriter> create(const std::string& path, int width, int height, int fps,
                                             std::string* error);
  /// Appends one frame: rows from the top, 3 bytes (R, G, B) per pixel, width * height * 3
  /// bytes of the size given to create().
  bool add_frame(const std::uint8_t* rgb, std::string* error);
  /// Flushes the encoder, writes the trailer and closes the file. Later calls fail.
  bool finish(std::string* error);
  /// The encoder used, e.g. "libx264" or "mpeg4".
  const std::string& codec() const;
  int frames_added() const;

  /// Without finish(): the file is closed as it is (possibly unplayable) and kept.
  ~MovieWriter();
  MovieWriter(const MovieWriter&) = delete;
  MovieWriter& operator=(const MovieWriter&) = delete;

 private:
  struct Impl;
  explicit MovieWriter(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

/// What a movie file holds (read by demuxing every packet of its first video stream).
struct MovieInfo {
  int width = 0, height = 0;
  int frames = 0;            ///< video packets = frames for the codecs written here
  double fps = 0.0;          ///< the stream's average frame rate
  std::string codec;         ///< e.g. "h264"
  std::string container;     ///< e.g. "mov,mp4,m4a,3gp,3g2,mj2"
};

/// Reads `path`; returns false and sets *error when it is not a movie with a video stream.
bool probe_movie(const std::string& path, MovieInfo* info, std::string* error);

}  // namespace ff::io
