// assess_bag BAG... [--out DIR] [--config FILE] [--bands FILE] [--scene FILE] [--force-threshold N] ...: the
// training assessment of recorded sessions, computed by the same accumulator as the online
// node from the messages' header stamps. One bag: writes DIR/assessment.yaml, assessment.md,
// the series (CSV) and the plots (scripts/assessment_plots.py) and prints a summary. Several
// bags (the sessions of one trainee, in order): one such folder per bag under DIR and a
// learning curve (DIR/learning_curve.md, .csv, .png). Exit codes: 0 ok, 1 a report could not
// be written (or plotted), 2 bad usage, unreadable bag or missing topics (one line on stderr).
//
// A bag without its index (the .bag.active a recorder killed with SIGKILL leaves) cannot be
// opened by rosbag::Bag, which refuses unindexed bags: it is reindexed into a temporary copy
// by `rosbag reindex` (the Python rosbag tool; the original is not touched), and what the
// copy holds is assessed, saying so in one line (on stdout; errors go to stderr).
#include <ros/message_traits.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "session_messages.h"
#include "tissue_trainer/core/assess/assessment_report.h"
#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/scene/display_surface.h"
#include "tissue_trainer/core/scene/scene.h"

namespace {

const char* kUsage =
    "usage: assess_bag BAG... [--out DIR] [--config FILE] [--bands FILE|none] [--scene FILE]\n"
    "                  [--no-plots]\n"
    "                  [--force-threshold N] [--movement-speed-start V] [--movement-speed-stop V]\n"
    "                  [--movement-min-pause S] [--resample-rate HZ] [--smoothing-time S]\n"
    "                  [--max-gap S] [--tip-topic T] [--contact-topic T] [--status-topic T]\n"
    "  --out DIR      where the report goes (default: assessment); several bags: a folder per\n"
    "                 bag under DIR and DIR/learning_curve.md\n"
    "  --config FILE  settings YAML (the node's config/assessment.yaml); flags override it\n"
    "  --bands FILE   expert/novice reference bands to score against (default:\n"
    "                 config/assessment_bands.yaml of the package; none: no score)\n"
    "  --scene FILE   the session's scene: its rest surface is drawn under the tip path\n"
    "  --no-plots     write no PNG plots\n";

#ifndef TT_DEFAULT_BANDS
#define TT_DEFAULT_BANDS ""
#endif
#ifndef TT_PLOT_SCRIPT
#define TT_PLOT_SCRIPT ""
#endif

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

double parseNumber(const std::string& flag, const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v))
    throw UsageError(flag + ": expected a number, got '" + text + "'");
  return v;
}

struct Options {
  std::vector<std::string> bags;
  std::string out = "assessment", config, bands = TT_DEFAULT_BANDS, scene;
  bool plots = true;
  std::map<std::string, double> numbers;  // flag -> value, applied over the config file
  tt::SessionTopics topics;
};

Options parse(int argc, char** argv) {
  Options o;
  const std::vector<std::string> numeric = {"--force-threshold", "--movement-speed-start",
                                            "--movement-speed-stop", "--movement-min-pause",
                                            "--resample-rate", "--smoothing-time", "--max-gap"};
  std::map<std::string, std::string*> text = {{"--out", &o.out}, {"--config", &o.config},
                                              {"--bands", &o.bands}, {"--scene", &o.scene},
                                              {"--tip-topic", &o.topics.tip},
                                              {"--contact-topic", &o.topics.contact},
                                              {"--status-topic", &o.topics.status}};
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool isNumeric = std::find(numeric.begin(), numeric.end(), arg) != numeric.end();
    if (isNumeric || text.count(arg)) {
      if (i + 1 >= argc) throw UsageError(arg + ": expected a value");
      const std::string value = argv[++i];
      if (isNumeric)
        o.numbers[arg] = parseNumber(arg, value);
      else
        *text[arg] = value;
    } else if (arg == "--no-plots") {
      o.plots = false;
    } else if (!arg.empty() && arg[0] == '-') {
      throw UsageError("unknown option '" + arg + "'");
    } else {
      o.bags.push_back(arg);
    }
  }
  if (o.bags.empty()) throw UsageError("missing BAG");
  const tt::SessionTopics& t = o.topics;
  if (t.tip == t.contact || t.tip == t.status || t.contact == t.status)
    throw UsageError("the tip, contact and status topics must differ");
  return o;
}

tt::AssessmentSettings settingsOf(const Options& o) {
  tt::AssessmentSettings s = o.config.empty() ? tt::AssessmentSettings{} : tt::loadAssessmentSettings(o.config);
  const std::map<std::string, double*> fields = {
      {"--force-threshold", &s.forceThreshold}, {"--movement-speed-start", &s.movementSpeedStart},
      {"--movement-speed-stop", &s.movementSpeedStop}, {"--movement-min-pause", &s.movementMinPause},
      {"--resample-rate", &s.resampleRate},
      {"--smoothing-time", &s.smoothingTime}, {"--max-gap", &s.maxGap}};
  for (const auto& [flag, value] : o.numbers) *fields.at(flag) = value;
  try {
    s.validate();
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  return s;
}

// Checks that every topic is in the bag with the expected type; throws naming what is wrong.
void checkTopics(const rosbag::Bag& bag, const std::string& path, const tt::SessionTopics& t) {
  const std::map<std::string, std::string> expected = {
      {t.tip, ros::message_traits::datatype<geometry_msgs::PoseStamped>()},
      {t.contact, ros::message_traits::datatype<tissue_trainer::ContactModel>()},
      {t.status, ros::message_traits::datatype<tissue_trainer::TissueStatus>()}};
  std::map<std::string, std::string> found;
  rosbag::View all(bag);
  for (const rosbag::ConnectionInfo* c : all.getConnections()) found[c->topic] = c->datatype;
  std::string missing;
  for (const auto& [topic, type] : expected) {
    const auto it = found.find(topic);
    if (it == found.end())
      missing += (missing.empty() ? "" : ", ") + topic;
    else if (it->second != type)
      throw std::runtime_error(path + ": topic " + topic + " is " + it->second + ", expected " + type);
  }
  if (!missing.empty()) throw std::runtime_error(path + ": missing topics: " + missing);
}

namespace fs = std::filesystem;

// The rest surface of a scene as CSV, a triangle a row (world metres), for the tip-path plot.
std::string tissueSurfaceCsv(const std::string& sceneFile) {
  const tt::Scene scene = tt::loadScene(sceneFile);
  const tt::DisplaySurface surface(scene);
  Eigen::Matrix3Xd vertices;
  surface.positions(scene.system.state.x, vertices);
  std::string out = "ax,ay,az,bx,by,bz,cx,cy,cz\n";
  char line[256];
  for (const tt::Triangle& t : surface.triangles()) {
    const Eigen::Vector3d a = vertices.col(t[0]), b = vertices.col(t[1]), c = vertices.col(t[2]);
    std::snprintf(line, sizeof line, "%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g\n", a.x(), a.y(), a.z(),
                  b.x(), b.y(), b.z(), c.x(), c.y(), c.z());
    out += line;
  }
  return out;
}

// The last non-empty line of a file ("" when there is none).
std::string lastLine(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line))
    if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  return last;
}

// A temporary folder removed with everything in it when this goes out of scope.
struct TemporaryFolder {
  fs::path path;
  TemporaryFolder() {
    std::string pattern = (fs::temp_directory_path() / "assess_bag.XXXXXX").string();
    if (!mkdtemp(pattern.data())) throw std::runtime_error("cannot create a temporary folder");
    path = pattern;
  }
  ~TemporaryFolder() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

// Runs `rosbag reindex --output-dir DIR BAG` and returns the reindexed copy; throws with the
// tool's last line when it fails.
std::string reindexCopy(const std::string& bag, const fs::path& dir) {
  const std::string log = (dir / "reindex.log").string();
  const std::string out = dir.string();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(bag + ": cannot start rosbag reindex");
  if (pid == 0) {
    if (!std::freopen(log.c_str(), "w", stdout) || !std::freopen(log.c_str(), "a", stderr)) _exit(127);
    execlp("rosbag", "rosbag", "reindex", "--quiet", "--output-dir", out.c_str(), bag.c_str(),
           static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    const std::string why = WIFEXITED(status) && WEXITSTATUS(status) == 127
                                ? "rosbag not found (install python3-rosbag)"
                                : lastLine(log);
    throw std::runtime_error(bag + ": unindexed, and rosbag reindex failed: " + why);
  }
  const fs::path copy = dir / fs::path(bag).filename();
  if (!fs::exists(copy)) throw std::runtime_error(bag + ": rosbag reindex wrote no copy");
  return copy.string();
}

// Opens the bag; an unindexed one is reindexed into a copy in tmp first (said on stdout).
void openBag(rosbag::Bag& bag, const std::string& path, std::unique_ptr<TemporaryFolder>& tmp) {
  if (!fs::is_regular_file(path)) throw std::runtime_error(path + ": cannot read the bag (no such file)");
  try {
    bag.open(path, rosbag::bagmode::Read);
    return;
  } catch (const rosbag::BagUnindexedException&) {
    bag.close();  // the refused bag stays open in `bag` otherwise
  }
  tmp = std::make_unique<TemporaryFolder>();
  const std::string copy = reindexCopy(path, tmp->path);
  std::printf("assess_bag: %s: unindexed (a recording that did not end cleanly); assessing a "
               "reindexed copy of what it holds\n",
              path.c_str());
  bag.open(copy, rosbag::bagmode::Read);
}

// The message, or an exception naming the topic when the bag's definition does not match.
template <class T>
boost::shared_ptr<T> instance(const rosbag::MessageInstance& m, const std::string& path) {
  boost::shared_ptr<T> msg = m.instantiate<T>();
  if (!msg)
    throw std::runtime_error(path + ": topic " + m.getTopic() + ": the recorded " + m.getDataType() +
                             " does not match this build's definition (md5 " + m.getMD5Sum() + ")");
  return msg;
}

// Reads the session topics of one bag into a report; throws naming what is wrong.
tt::AssessmentReport assessBag(const std::string& path, const Options& options,
                               const tt::AssessmentSettings& settings, std::size_t& messages) {
  tt::SessionFeeder feeder(settings);
  messages = 0;
  try {
    rosbag::Bag bag;
    std::unique_ptr<TemporaryFolder> tmp;
    openBag(bag, path, tmp);
    checkTopics(bag, path, options.topics);
    const tt::SessionTopics& t = options.topics;
    rosbag::View view(bag, rosbag::TopicQuery({t.tip, t.contact, t.status}));
    for (const rosbag::MessageInstance& m : view) {
      ++messages;
      if (m.getTopic() == t.tip)
        feeder.feed(*instance<geometry_msgs::PoseStamped>(m, path));
      else if (m.getTopic() == t.contact)
        feeder.feed(*instance<tissue_trainer::ContactModel>(m, path));
      else
        feeder.feed(*instance<tissue_trainer::TissueStatus>(m, path));
    }
  } catch (const rosbag::BagException& e) {
    throw std::runtime_error(path + ": cannot read the bag (" + e.what() + ")");
  }
  return feeder.report();
}

// Runs `/usr/bin/python3 SCRIPT MODE DIR`; false (after saying why on stderr) when it fails.
bool runPlots(const std::string& mode, const std::string& dir) {
  const char* env = std::getenv("TT_ASSESSMENT_PLOTS");
  const std::string script = env && *env ? env : TT_PLOT_SCRIPT;
  if (script.empty() || !fs::exists(script)) {
    std::fprintf(stderr, "assess_bag: no plots: the plotting script '%s' is missing (set TT_ASSESSMENT_PLOTS)\n",
                 script.c_str());
    return false;
  }
  std::fflush(stdout);
  const pid_t pid = fork();
  if (pid < 0) return false;
  if (pid == 0) {
    // Debian's interpreter, where python3-matplotlib is (not a python3 earlier on PATH).
    execl("/usr/bin/python3", "python3", script.c_str(), mode.c_str(), dir.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  const bool ok = waitpid(pid, &status, 0) == pid && WIFEXITED(status) && WEXITSTATUS(status) == 0;
  if (!ok)
    std::fprintf(stderr, "assess_bag: %s: the plots failed (python3 %s %s, exit %d)\n", dir.c_str(),
                 script.c_str(), mode.c_str(), WIFEXITED(status) ? WEXITSTATUS(status) : -1);
  return ok;
}

// "NN_stem" for the folder of the i-th of several bags.
std::string sessionFolder(std::size_t index, const std::string& bag) {
  char prefix[32];
  std::snprintf(prefix, sizeof prefix, "%02zu_", index + 1);
  std::string stem = fs::path(bag).filename().string();
  for (const char* ext : {".active", ".bag"})
    if (stem.size() > std::strlen(ext) && stem.compare(stem.size() - std::strlen(ext), std::string::npos, ext) == 0)
      stem.erase(stem.size() - std::strlen(ext));
  return prefix + stem;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  tt::AssessmentSettings settings;
  tt::ReferenceBands bands;
  try {
    options = parse(argc, argv);
    settings = settingsOf(options);
    if (options.bands != "none") {
      if (options.bands.empty()) throw UsageError("--bands: no default bands file in this build; give one or 'none'");
      bands = tt::loadReferenceBands(options.bands);
    }
  } catch (const UsageError& e) {
    std::fprintf(stderr, "assess_bag: %s\n%s", e.what(), kUsage);
    return 2;
  } catch (const tt::InputError& e) {
    std::fprintf(stderr, "assess_bag: %s\n", e.what());
    return 2;
  }
  const bool scored = options.bands != "none";
  std::string tissueSurface;
  if (!options.scene.empty()) {
    try {
      tissueSurface = tissueSurfaceCsv(options.scene);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "assess_bag: --scene: %s\n", e.what());
      return 2;
    }
  }

  // Read every bag first: a bad one stops before anything is written.
  std::vector<tt::SessionResult> sessions;
  std::vector<std::size_t> messages(options.bags.size());
  try {
    for (std::size_t i = 0; i < options.bags.size(); ++i) {
      tt::SessionResult r;
      r.label = options.bags[i];
      r.dir = options.bags.size() == 1 ? "." : sessionFolder(i, options.bags[i]);
      r.report = assessBag(options.bags[i], options, settings, messages[i]);
      if (scored) r.score = tt::scoreAssessment(r.report, bands);
      sessions.push_back(std::move(r));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "assess_bag: %s\n", e.what());
    return 2;
  }

  int status = 0;
  try {
    for (std::size_t i = 0; i < sessions.size(); ++i) {
      const tt::SessionResult& r = sessions[i];
      const std::string dir = (fs::path(options.out) / r.dir).lexically_normal().string();
      const tt::SkillScore* score = scored ? &r.score : nullptr;
      const std::string yaml = tt::writeAssessment(r.report, dir, options.bags[i], score);
      const fs::path surfaceCsv = fs::path(dir) / "tissue_surface.csv";
      if (tissueSurface.empty()) {
        std::error_code ignored;  // an earlier report's surface is not this session's
        fs::remove(surfaceCsv, ignored);
      } else {
        std::ofstream csv(surfaceCsv.string());
        csv << tissueSurface;
        if (!csv) throw std::runtime_error(surfaceCsv.string() + ": cannot write the file");
      }
      std::printf("assess_bag: %s: %zu messages -> %s\n", options.bags[i].c_str(), messages[i], yaml.c_str());
      if (options.plots) {
        if (runPlots("report", dir))
          tt::writeAssessmentMarkdown(r.report, dir, options.bags[i], score);
        else
          status = 1;
      }
      std::printf("%s", tt::assessmentSummary(r.report, score).c_str());
    }
    if (sessions.size() > 1) {
      fs::create_directories(options.out);
      const fs::path dir(options.out);
      std::ofstream((dir / "learning_curve.csv").string()) << tt::learningCurveCsv(sessions);
      const bool plotted = options.plots && runPlots("curve", options.out);
      if (options.plots && !plotted) status = 1;
      std::ofstream md((dir / "learning_curve.md").string());
      md << tt::learningCurveMarkdown(sessions, plotted);
      if (!md) throw std::runtime_error((dir / "learning_curve.md").string() + ": cannot write the file");
      std::printf("assess_bag: learning curve of %zu sessions -> %s\n", sessions.size(),
                  (dir / "learning_curve.md").string().c_str());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "assess_bag: %s\n", e.what());
    return 1;
  }
  return status;
}
