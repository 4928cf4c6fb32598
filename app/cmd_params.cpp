// `ardrone-gs params [--classifier NAME] [--odometry] [--assist]`: every named parameter that
// `--set` accepts (replay, eval, record, the window's Classifier panel; odometry) and that
// `eval-assist --assist-set` accepts, with its default, range and meaning, read from the same
// tables the code applies them with.
#include "app/assist.hpp"
#include "app/command.hpp"
#include "vision/classifier.hpp"
#include "vision/odometry.hpp"

#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace gs::app::cmd_params {
namespace {

struct Opts {
    std::vector<std::string> classifiers;
    bool odometry = false;
    bool assist = false;
};

std::string value_text(const vision::ParamInfo& p, double v) {
    if (p.type == vision::ParamType::Boolean) return v != 0 ? "1" : "0";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

void print_table(const std::string& title, const std::vector<vision::ParamInfo>& params) {
    std::cout << title << '\n';
    for (const auto& p : params) {
        const std::string range = p.type == vision::ParamType::Boolean
                                      ? "0|1"
                                      : value_text(p, p.min) + ".." + value_text(p, p.max);
        std::printf("  %-34s %-10s [%s]  %s\n", p.name.c_str(), value_text(p, p.value).c_str(),
                    range.c_str(), p.description.c_str());
    }
    std::cout << '\n';
}

void run(const Opts& o) {
    const bool all = o.classifiers.empty() && !o.odometry && !o.assist;
    std::vector<std::string> names = o.classifiers;
    if (all)
        for (auto n : vision::classifier_names()) names.emplace_back(n);
    for (const auto& n : names) {
        auto c = vision::make_classifier(n, {});
        if (!c) throw fail("unknown classifier '" + n + "'");
        print_table("Classifier '" + n + "' (replay, eval, record: --set KEY=VALUE)", c->params());
    }
    if (all || o.odometry) {
        const vision::OdometryParams defaults;
        print_table("Visual odometry (odometry: --set KEY=VALUE)",
                    vision::odometry_param_table().list(defaults));
    }
    if (all || o.assist) {
        static const AssistParams defaults{};  // static: GCC 12 warns falsely on a local
        print_table("Collision assist (eval-assist: --assist-set KEY=VALUE)",
                    assist_param_table().list(defaults));
    }
}

const CommandRegistration reg(70, [](CLI::App& root) {
    auto o = std::make_shared<Opts>();
    auto* sub = root.add_subcommand(
        "params",
        "List every classifier and odometry parameter --set accepts, and the assist's "
        "--assist-set (default, range)");
    std::vector<std::string> names;
    for (auto n : vision::classifier_names()) names.emplace_back(n);
    sub->add_option("--classifier", o->classifiers, "Only this classifier's (repeatable)")
        ->check(CLI::IsMember(names));
    sub->add_flag("--odometry", o->odometry, "Only the visual odometry's");
    sub->add_flag("--assist", o->assist, "Only the collision assist's");
    set_action(*sub, [o] { run(*o); });
});

}  // namespace
}  // namespace gs::app::cmd_params
