#pragma once
// The corpus of public Mitsuba test scenes (../shared/scenes-corpus beside the shared scenes; its manifest.tsv:
// folder, main file, ...) as the parameters of the tests that walk it. Where the corpus is absent the list holds one
// empty entry, whose test skips saying why (named "absent").
//
// CLRADIOSITY_SCENES_CORPUS names another folder laid out the same way (a manifest.tsv whose first two columns are
// the scene's folder and its main file), so that the same tests measure a set assembled elsewhere: the Mitsuba peer
// over it (docs/scenes.md, "The peer at scale"), and the corpus test listing what it refuses.
#include <gtest/gtest.h>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace clr::test {

inline const std::filesystem::path kCorpus = [] {
  const char* other = std::getenv("CLRADIOSITY_SCENES_CORPUS");
  return other && *other ? std::filesystem::path(other)
                         : std::filesystem::path(CLR_SHARED_SCENES) / ".." / "scenes-corpus";
}();

struct CorpusScene {
  std::string dir, main_xml;  // empty where the corpus is absent
};
inline void PrintTo(const CorpusScene& s, std::ostream* os) { *os << s.dir; }

inline std::vector<CorpusScene> corpus_scenes() {
  std::vector<CorpusScene> out;
  std::ifstream in(kCorpus / "manifest.tsv");
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    CorpusScene s;
    if (std::getline(fields, s.dir, '\t') && std::getline(fields, s.main_xml, '\t')) out.push_back(s);
  }
  if (out.empty()) out.push_back({});
  return out;
}

// gtest parameter names for `scenes`: each folder with every character but letters and digits as '_' ("absent" for
// the empty entry). Folders that differ only in punctuation ("scene-init", "scene_init", as an assembled set had)
// would get one name twice, on which gtest aborts the whole binary: those get their index appended.
inline std::vector<std::string> corpus_test_names(const std::vector<CorpusScene>& scenes) {
  std::vector<std::string> names;
  std::map<std::string, int> uses;
  for (const auto& s : scenes) {
    std::string n = s.dir.empty() ? "absent" : s.dir;
    for (char& c : n)
      if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    ++uses[n];
    names.push_back(n);
  }
  for (std::size_t i = 0; i < names.size(); ++i)
    if (uses[names[i]] > 1) names[i] += "_" + std::to_string(i);
  return names;
}
inline std::string corpus_test_name(const ::testing::TestParamInfo<CorpusScene>& p) {
  static const std::vector<std::string> names = corpus_test_names(corpus_scenes());
  return p.index < names.size() ? names[p.index] : "scene_" + std::to_string(p.index);
}

}  // namespace clr::test
