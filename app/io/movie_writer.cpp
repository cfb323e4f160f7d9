/// \file movie_writer.cpp
/// MovieWriter and probe_movie on FFmpeg's libraries (the send/receive encoding API of
/// libavcodec >= 57), opened with dlopen on first use. Every FFmpeg object is owned by Impl and
/// freed in its destructor.

#include "app/io/movie_writer.h"

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#ifdef FF_HAVE_LIBAV
extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/error.h>
#include <libavutil/imgutils.h>
#include <libavutil/log.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}
#include <dlfcn.h>
#endif

namespace ff::io {

#ifdef FF_HAVE_LIBAV

namespace {

// FFmpeg's libraries are opened when a movie is first written or probed, not at start-up: with
// their codecs' own dependencies they are about 90 of the ~235 libraries the process would load,
// and 40 ms of every flexframe start (docs/performance.md). The sonames are those of the headers
// this file was compiled with.
#define FF_AV_FUNCTIONS(X) \
  X(avutil, av_strerror) \
  X(avutil, av_log_get_level) \
  X(avutil, av_log_set_level) \
  X(avformat, av_write_trailer) \
  X(avformat, avio_closep) \
  X(swscale, sws_freeContext) \
  X(avcodec, av_packet_free) \
  X(avutil, av_frame_free) \
  X(avcodec, avcodec_free_context) \
  X(avformat, avformat_free_context) \
  X(avcodec, avcodec_send_frame) \
  X(avcodec, avcodec_receive_packet) \
  X(avcodec, av_packet_rescale_ts) \
  X(avformat, av_interleaved_write_frame) \
  X(avformat, avformat_alloc_output_context2) \
  X(avcodec, avcodec_find_encoder_by_name) \
  X(avcodec, avcodec_find_encoder) \
  X(avformat, avformat_new_stream) \
  X(avcodec, avcodec_alloc_context3) \
  X(avutil, av_frame_alloc) \
  X(avcodec, av_packet_alloc) \
  X(avutil, av_opt_set) \
  X(avcodec, avcodec_open2) \
  X(avcodec, avcodec_parameters_from_context) \
  X(avutil, av_frame_get_buffer) \
  X(swscale, sws_getContext) \
  X(avformat, avio_open) \
  X(avformat, avformat_write_header) \
  X(avutil, av_frame_make_writable) \
  X(swscale, sws_scale) \
  X(avformat, avformat_open_input) \
  X(avformat, avformat_find_stream_info) \
  X(avformat, av_find_best_stream) \
  X(avcodec, avcodec_get_name) \
  X(avformat, av_read_frame) \
  X(avcodec, av_packet_unref) \
  X(avformat, avformat_close_input)

struct AvApi {
#define FF_AV_POINTER(lib, name) decltype(&::name) name = nullptr;
  FF_AV_FUNCTIONS(FF_AV_POINTER)
#undef FF_AV_POINTER
  std::string error;  // why the libraries could not be loaded ("" when they were)
};

AvApi load_av_api() {
  AvApi api;
  struct Library {
    const char* name;
    std::string soname;
    void* handle = nullptr;
  };
  Library libs[] = {{"avutil", "libavutil.so." + std::to_string(LIBAVUTIL_VERSION_MAJOR)},
                    {"swscale", "libswscale.so." + std::to_string(LIBSWSCALE_VERSION_MAJOR)},
                    {"avcodec", "libavcodec.so." + std::to_string(LIBAVCODEC_VERSION_MAJOR)},
                    {"avformat", "libavformat.so." + std::to_string(LIBAVFORMAT_VERSION_MAJOR)}};
  for (Library& l : libs) {
    l.handle = dlopen(l.soname.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (l.handle == nullptr) {
      const char* why = dlerror();
      api.error = "FFmpeg's " + l.soname + " could not be loaded (" + (why ? why : "unknown reason") +
                  "); on Debian: apt-get install libavcodec59 libavformat59 libswscale6";
      return api;
    }
  }
  auto handle = [&](const char* lib) {
    for (const Library& l : libs)
      if (std::strcmp(l.name, lib) == 0) return l.handle;
    return static_cast<void*>(nullptr);
  };
#define FF_AV_RESOLVE(lib, fn)                                                               \
  api.fn = reinterpret_cast<decltype(api.fn)>(dlsym(handle(#lib), #fn));                     \
  if (api.fn == nullptr && api.error.empty()) api.error = "FFmpeg's lib" #lib " has no " #fn;
  FF_AV_FUNCTIONS(FF_AV_RESOLVE)
#undef FF_AV_RESOLVE
  return api;
}

// loaded once, on first use, by whichever thread gets there first
const AvApi& api() {
  static const AvApi loaded = load_av_api();
  return loaded;
}

std::string av_error(int code) {
  char buf[AV_ERROR_MAX_STRING_SIZE] = {0};
  api().av_strerror(code, buf, sizeof buf);
  return buf;
}

// x264 and the muxer report progress at info level; keep warnings and errors only
void quiet_ffmpeg_logs() {
  if (api().av_log_get_level() > AV_LOG_ERROR) api().av_log_set_level(AV_LOG_ERROR);
}

}  // namespace

std::string movie_support() { return api().error; }

struct MovieWriter::Impl {
  std::string path, codec_name;
  int width = 0, height = 0;            // of the caller's frames
  int enc_width = 0, enc_height = 0;    // even sizes for yuv420p
  AVFormatContext* format = nullptr;
  AVCodecContext* encoder = nullptr;
  AVStream* stream = nullptr;
  AVFrame* frame = nullptr;
  AVPacket* packet = nullptr;
  SwsContext* sws = nullptr;
  std::vector<std::uint8_t> padded;     // caller's frame grown to the even size
  std::int64_t next_pts = 0;
  bool header_written = false, finished = false;

  ~Impl() {
    if (header_written && !finished) api().av_write_trailer(format);
    if (format != nullptr && format->pb != nullptr) api().avio_closep(&format->pb);
    api().sws_freeContext(sws);
    api().av_packet_free(&packet);
    api().av_frame_free(&frame);
    api().avcodec_free_context(&encoder);
    api().avformat_free_context(format);
  }

  std::string what(const std::string& s) const { return "movie '" + path + "': " + s; }

  // sends `f` (nullptr = flush) and writes every packet the encoder returns
  bool encode(AVFrame* f, std::string* error) {
    int rc = api().avcodec_send_frame(encoder, f);
    if (rc < 0) return *error = what("encoding failed: " + av_error(rc)), false;
    while (true) {
      rc = api().avcodec_receive_packet(encoder, packet);
      if (rc == AVERROR(EAGAIN) || rc == AVERROR_EOF) return true;
      if (rc < 0) return *error = what("encoding failed: " + av_error(rc)), false;
      api().av_packet_rescale_ts(packet, encoder->time_base, stream->time_base);
      packet->stream_index = stream->index;
      rc = api().av_interleaved_write_frame(format, packet);  // takes the packet's data
      if (rc < 0) return *error = what("writing failed: " + av_error(rc)), false;
    }
  }
};

MovieWriter::MovieWriter(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
MovieWriter::~MovieWriter() = default;
const std::string& MovieWriter::codec() const { return impl_->codec_name; }
int MovieWriter::frames_added() const { return static_cast<int>(impl_->next_pts); }

std::unique_ptr<MovieWriter> MovieWriter::create(const std::string& path, int width, int height, int fps,
                                                 std::string* error) {
  if (!api().error.empty()) {  // no Impl either: its destructor calls into the libraries
    if (error) *error = "movie '" + path + "': " + api().error;
    return nullptr;
  }
  quiet_ffmpeg_logs();
  auto m = std::make_unique<Impl>();
  m->path = path;
  std::string dummy;
  if (error == nullptr) error = &dummy;
  auto fail = [&](const std::string& why) {
    *error = m->what(why);
    return nullptr;
  };
  if (width < 2 || height < 2 || width > 16384 || height > 16384) return fail("bad frame size");
  if (fps < 1 || fps > 240) return fail("frame rate must be 1..240 per second");
  m->width = width;
  m->height = height;
  m->enc_width = width + (width % 2);
  m->enc_height = height + (height % 2);

  int rc = api().avformat_alloc_output_context2(&m->format, nullptr, "mp4", path.c_str());
  if (rc < 0 || m->format == nullptr) return fail("no MP4 muxer: " + av_error(rc));
  const AVCodec* codec = api().avcodec_find_encoder_by_name("libx264");
  if (codec == nullptr) codec = api().avcodec_find_encoder(AV_CODEC_ID_MPEG4);
  if (codec == nullptr) return fail("libavcodec has neither an H.264 (libx264) nor an MPEG-4 encoder");
  m->codec_name = codec->name;

  m->stream = api().avformat_new_stream(m->format, nullptr);
  m->encoder = api().avcodec_alloc_context3(codec);
  m->frame = api().av_frame_alloc();
  m->packet = api().av_packet_alloc();
  if (!m->stream || !m->encoder || !m->frame || !m->packet) return fail("out of memory");
  AVCodecContext* c = m->encoder;
  c->width = m->enc_width;
  c->height = m->enc_height;
  c->pix_fmt = AV_PIX_FMT_YUV420P;
  c->time_base = AVRational{1, fps};
  c->framerate = AVRational{fps, 1};
  c->gop_size = 2 * fps;
  c->thread_count = 2;  // this project's machines have two cores shared with the rest of the run
  if (m->codec_name == "libx264") {
    api().av_opt_set(c->priv_data, "preset", "medium", 0);
    api().av_opt_set(c->priv_data, "crf", "20", 0);
  } else {
    // MPEG-4 at a fixed quantizer: sharp lines and text without tuning a bit rate
    c->flags |= AV_CODEC_FLAG_QSCALE;
    c->global_quality = FF_QP2LAMBDA * 3;
  }
  if (m->format->oformat->flags & AVFMT_GLOBALHEADER) c->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
  rc = api().avcodec_open2(c, codec, nullptr);
  if (rc < 0) return fail("cannot open the " + m->codec_name + " encoder: " + av_error(rc));
  rc = api().avcodec_parameters_from_context(m->stream->codecpar, c);
  if (rc < 0) return fail("stream parameters: " + av_error(rc));
  m->stream->time_base = c->time_base;
  m->stream->avg_frame_rate = c->framerate;

  m->frame->format = c->pix_fmt;
  m->frame->width = c->width;
  m->frame->height = c->height;
  rc = api().av_frame_get_buffer(m->frame, 0);
  if (rc < 0) return fail("frame buffer: " + av_error(rc));
  m->sws = api().sws_getContext(m->enc_width, m->enc_height, AV_PIX_FMT_RGB24, m->enc_width, m->enc_height,
                          AV_PIX_FMT_YUV420P, SWS_BICUBIC, nullptr, nullptr, nullptr);
  if (m->sws == nullptr) return fail("no RGB to YUV converter");
  m->padded.assign(static_cast<std::size_t>(m->enc_width) * m->enc_height * 3, 0);

  rc = api().avio_open(&m->format->pb, path.c_str(), AVIO_FLAG_WRITE);
  if (rc < 0) return fail("cannot open for writing: " + av_error(rc));
  rc = api().avformat_write_header(m->format, nullptr);
  if (rc < 0) return fail("cannot write the MP4 header: " + av_error(rc));
  m->header_written = true;
  return std::unique_ptr<MovieWriter>(new MovieWriter(std::move(m)));
}

bool MovieWriter::add_frame(const std::uint8_t* rgb, std::string* error) {
  Impl& m = *impl_;
  std::string dummy;
  if (error == nullptr) error = &dummy;
  if (m.finished) return *error = m.what("already finished"), false;
  // copy into the even-sized buffer, repeating the last column and row when padding
  const std::size_t src_row = static_cast<std::size_t>(m.width) * 3, dst_row = static_cast<std::size_t>(m.enc_width) * 3;
  for (int r = 0; r < m.enc_height; ++r) {
    const std::uint8_t* src = rgb + static_cast<std::size_t>(std::min(r, m.height - 1)) * src_row;
    std::uint8_t* dst = m.padded.data() + static_cast<std::size_t>(r) * dst_row;
    std::memcpy(dst, src, src_row);
    if (m.enc_width != m.width) std::memcpy(dst + src_row, src + src_row - 3, 3);
  }
  int rc = api().av_frame_make_writable(m.frame);
  if (rc < 0) return *error = m.what("frame buffer: " + av_error(rc)), false;
  const std::uint8_t* src_planes[1] = {m.padded.data()};
  const int src_strides[1] = {static_cast<int>(dst_row)};
  api().sws_scale(m.sws, src_planes, src_strides, 0, m.enc_height, m.frame->data, m.frame->linesize);
  m.frame->pts = m.next_pts++;
  return m.encode(m.frame, error);
}

bool MovieWriter::finish(std::string* error) {
  Impl& m = *impl_;
  std::string dummy;
  if (error == nullptr) error = &dummy;
  if (m.finished) return *error = m.what("already finished"), false;
  const bool ok = m.encode(nullptr, error);
  m.finished = true;
  const int rc = api().av_write_trailer(m.format);
  if (rc < 0) return *error = m.what("cannot write the MP4 trailer: " + av_error(rc)), false;
  if (m.format->pb != nullptr) api().avio_closep(&m.format->pb);
  return ok;
}

bool probe_movie(const std::string& path, MovieInfo* info, std::string* error) {
  if (!api().error.empty()) {
    if (error) *error = "movie '" + path + "': " + api().error;
    return false;
  }
  quiet_ffmpeg_logs();
  AVFormatContext* fmt = nullptr;
  auto fail = [&](const std::string& why) {
    if (error) *error = "movie '" + path + "': " + why;
    if (fmt != nullptr) api().avformat_close_input(&fmt);
    return false;
  };
  int rc = api().avformat_open_input(&fmt, path.c_str(), nullptr, nullptr);
  if (rc < 0) return fail(av_error(rc));
  rc = api().avformat_find_stream_info(fmt, nullptr);
  if (rc < 0) return fail(av_error(rc));
  const int video = api().av_find_best_stream(fmt, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
  if (video < 0) return fail("no video stream");
  const AVStream* s = fmt->streams[video];
  info->width = s->codecpar->width;
  info->height = s->codecpar->height;
  info->codec = api().avcodec_get_name(s->codecpar->codec_id);
  info->container = fmt->iformat->name;
  info->fps = s->avg_frame_rate.den != 0 ? av_q2d(s->avg_frame_rate) : 0.0;
  info->frames = 0;
  AVPacket* pkt = api().av_packet_alloc();
  while (pkt != nullptr && api().av_read_frame(fmt, pkt) >= 0) {
    if (pkt->stream_index == video) ++info->frames;
    api().av_packet_unref(pkt);
  }
  api().av_packet_free(&pkt);
  api().avformat_close_input(&fmt);
  return true;
}

#else  // no FFmpeg libraries in this build

std::string movie_support() {
  return "this flexframe was built without FFmpeg's libraries (libavcodec, libavformat, libswscale)";
}

struct MovieWriter::Impl {
  std::string codec_name;
};
MovieWriter::MovieWriter(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
MovieWriter::~MovieWriter() = default;
const std::string& MovieWriter::codec() const { return impl_->codec_name; }
int MovieWriter::frames_added() const { return 0; }
std::unique_ptr<MovieWriter> MovieWriter::create(const std::string& path, int, int, int, std::string* error) {
  if (error) *error = "movie '" + path + "': " + movie_support();
  return nullptr;
}
bool MovieWriter::add_frame(const std::uint8_t*, std::string* error) {
  if (error) *error = movie_support();
  return false;
}
bool MovieWriter::finish(std::string* error) {
  if (error) *error = movie_support();
  return false;
}
bool probe_movie(const std::string& path, MovieInfo*, std::string* error) {
  if (error) *error = "movie '" + path + "': " + movie_support();
  return false;
}

#endif

}  // namespace ff::io
