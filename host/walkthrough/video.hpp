#pragma once
// A walkthrough's frames as one video file, made by ffmpeg (Debian `ffmpeg`) when it is installed: the frames need
// no video, so without it `--video` is refused before any rendering, with what to install.
#include <filesystem>

namespace clr::walkthrough {

// InputError naming `--video` unless `video` has a container this writes (.mp4: H.264, .webm: VP9, .gif) and
// ffmpeg is on PATH.
void require_video_writer(const std::filesystem::path& video);

// Encodes FRAMES_DIR's frame_NNNNN.png (all `frames` of them) at `fps` into `video`, atomically.
// false when a stop was requested while ffmpeg ran (ffmpeg is stopped too, no video is left).
bool write_video(const std::filesystem::path& frames_dir, std::size_t frames, double fps,
                 const std::filesystem::path& video);

}  // namespace clr::walkthrough
