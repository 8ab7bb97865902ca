#include "walkthrough/video.hpp"

#include <stdexcept>
#include <string>
#include <vector>

#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "common/stop_signal.hpp"
#include "common/subprocess.hpp"

namespace clr::walkthrough {
namespace {

// ffmpeg's muxer and codec options for each container: the temporary name hides the extension from ffmpeg.
std::vector<std::string> format_arguments(const std::filesystem::path& video) {
  const std::string ext = video.extension().string();
  // H.264 in 4:2:0 needs even sizes: a frame of odd size is padded by one pixel.
  if (ext == ".mp4")
    return {"-c:v", "libx264", "-pix_fmt", "yuv420p", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-f", "mp4"};
  if (ext == ".webm") return {"-c:v", "libvpx-vp9", "-pix_fmt", "yuv420p", "-f", "webm"};
  if (ext == ".gif") return {"-f", "gif"};
  return {};
}

// The frames' pattern as ffmpeg's image2 demuxer reads it: a '%' of the folder's own name doubled (it would start a
// pattern), the path absolute (a name starting with '-' would read as an option, one like "a:b" as a protocol).
std::string frames_pattern(const std::filesystem::path& frames_dir) {
  std::string folder;
  for (const char c : std::filesystem::absolute(frames_dir).string())
    folder += c == '%' ? std::string("%%") : std::string(1, c);
  return folder + "/frame_%05d.png";
}

}  // namespace

void require_video_writer(const std::filesystem::path& video) {
  if (format_arguments(video).empty())
    throw InputError("--video " + video.string() + ": give a .mp4, .webm or .gif file");
  if (find_program("ffmpeg").empty())
    throw InputError("--video: ffmpeg is not installed (apt-get install ffmpeg); the frames alone need no --video");
}

bool write_video(const std::filesystem::path& frames_dir, std::size_t frames, double fps,
                 const std::filesystem::path& video) {
  struct Stopped {};
  try {
    write_atomically(video, [&](const std::filesystem::path& tmp) {
      std::vector<std::string> args = {"ffmpeg",     "-y",
                                       "-loglevel",  "error",
                                       "-framerate", std::to_string(fps),
                                       "-i",         frames_pattern(frames_dir),
                                       "-frames:v",  std::to_string(frames)};
      for (auto& a : format_arguments(video)) args.push_back(a);
      args.push_back(std::filesystem::absolute(tmp).string());  // absolute for the same reasons as the frames
      const ProgramResult r = run_program(args, false);
      if (stop_requested()) throw Stopped{};  // ffmpeg was stopped too: its partial file is removed with the temporary
      if (!r.ok) throw std::runtime_error("ffmpeg failed to write " + video.string() + ": " + r.cause);
    });
  } catch (const Stopped&) {
    return false;
  }
  return true;
}

}  // namespace clr::walkthrough
