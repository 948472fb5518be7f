// The ParaView colour-map preset viz/paper_colormap.json (ParaView's JSON preset format: a list of
// presets, each with a name, a colour space and RGBPoints as x, r, g, b quadruples) holds the
// colour map render_snapshot draws with (viz::energy_colour): the same control points, and between
// them the same linear interpolation at every hundredth of the scale.
#define BOOST_TEST_MODULE viz_colour_preset
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "snapshot_view.hpp"

BOOST_AUTO_TEST_CASE(the_paraview_preset_is_the_renderers_colour_map) {
    std::ifstream in(PAPER_COLORMAP);
    BOOST_TEST_REQUIRE(static_cast<bool>(in));
    const auto presets = nlohmann::json::parse(in);
    BOOST_TEST_REQUIRE(presets.is_array());
    BOOST_TEST_REQUIRE(presets.size() == 1u);
    const auto& preset = presets[0];
    BOOST_TEST(preset.at("ColorSpace").get<std::string>() == "RGB");
    BOOST_TEST(!preset.at("Name").get<std::string>().empty());
    const auto points = preset.at("RGBPoints").get<std::vector<double>>();
    BOOST_TEST_REQUIRE(points.size() == 16u);  // four control points
    for (std::size_t p = 0; p < points.size(); p += 4) {
        const auto want = viz::energy_colour(points[p]);
        for (int k = 0; k < 3; ++k) BOOST_TEST(points[p + 1 + k] == want[k], "point at " << points[p] << ", channel " << k);
    }
    BOOST_TEST(points.front() == 0.0);
    BOOST_TEST(points[12] == 1.0);
    for (int i = 0; i <= 100; ++i) {  // ParaView interpolates linearly in RGB between the points
        const double u = i / 100.0;
        std::size_t p = 0;
        while (p + 4 < 12 && points[p + 4] < u) p += 4;
        const double t = (u - points[p]) / (points[p + 4] - points[p]);
        const auto want = viz::energy_colour(u);
        for (int k = 0; k < 3; ++k)
            BOOST_TEST(std::abs(points[p + 1 + k] + t * (points[p + 5 + k] - points[p + 1 + k]) - want[k]) < 1e-12, "u = " << u);
    }
}
