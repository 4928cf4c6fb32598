// parse_navdata against the four real captures (expected values from docs/protocol.md §7.2/§7.3 and
// fixtures SOURCES.md), the §7.4 bootstrap bytes, and malformed input.
#include "drone/protocol/navdata.hpp"

#include "drone/protocol/navdata_layout.hpp"
#include "support/navdata_fixtures.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <vector>

namespace gs::protocol::navdata {
namespace {

using test::read_fixture;

// The fixture tables print floats as their exact double expansion; compare bit-exactly.
float f(double v) {
    return static_cast<float>(v);
}

Navdata parse_ok(const std::vector<std::uint8_t>& bytes) {
    auto r = parse_navdata(bytes);
    if (!r) ADD_FAILURE() << to_string(r.error());
    return r ? *r : Navdata{};
}

void expect_state_bits(DroneState s, const std::set<unsigned>& set_bits) {
    for (unsigned i = 0; i < 32; ++i) {
        EXPECT_EQ(s.bit(i), set_bits.count(i) == 1)
            << "bit " << i << " " << kDroneStateBits[i].name;
    }
}

// ---- node-ar-drone_navdata.bin (§7.2)
// -------------------------------------------------------------

TEST(NavdataFull, HeaderAndStateBitsByName) {
    const Navdata nd = parse_ok(read_fixture(test::kNavdataFull));
    EXPECT_EQ(nd.header.magic, 0x55667788U);
    EXPECT_EQ(nd.header.drone_state.raw, 0x4F8000D0U);
    EXPECT_EQ(nd.header.sequence, 300711U);
    EXPECT_EQ(nd.header.vision_defined, 1U);
    const DroneState s = nd.header.drone_state;
    expect_state_bits(s, {4, 6, 7, 23, 24, 25, 26, 27, 30});
    EXPECT_FALSE(s.fly());
    EXPECT_FALSE(s.video());
    EXPECT_FALSE(s.vision());
    EXPECT_FALSE(s.control());
    EXPECT_TRUE(s.altitude());
    EXPECT_FALSE(s.user_feedback_start());
    EXPECT_TRUE(s.command());
    EXPECT_TRUE(s.camera());
    EXPECT_FALSE(s.travelling());
    EXPECT_FALSE(s.usb());
    EXPECT_FALSE(s.navdata_demo());
    EXPECT_FALSE(s.navdata_bootstrap());
    EXPECT_FALSE(s.motors() || s.com_lost() || s.software_fault() || s.vbat_low() || s.user_el() ||
                 s.timer_elapsed() || s.magneto_needs_calib() || s.angles_out_of_range() ||
                 s.wind() || s.ultrasound() || s.cutout());
    EXPECT_TRUE(s.pic_version());
    EXPECT_TRUE(s.atcodec_thread_on() && s.navdata_thread_on() && s.video_thread_on() &&
                s.acq_thread_on());
    EXPECT_FALSE(s.ctrl_watchdog());
    EXPECT_FALSE(s.adc_watchdog());
    EXPECT_TRUE(s.com_watchdog());
    EXPECT_FALSE(s.emergency());
    EXPECT_EQ(set_bit_names(s),
              "ALTITUDE COMMAND CAMERA PIC_VERSION ATCODEC_THREAD_ON NAVDATA_THREAD_ON "
              "VIDEO_THREAD_ON ACQ_THREAD_ON COM_WATCHDOG");
}

TEST(NavdataFull, OptionsInWireOrderAndChecksum) {
    const Navdata nd = parse_ok(read_fixture(test::kNavdataFull));
    const std::vector<std::array<unsigned, 3>> expected = {
        {16, 0, 148},   {164, 1, 8},     {172, 2, 52},    {224, 3, 46},     {270, 4, 16},
        {286, 5, 12},   {298, 6, 88},    {386, 7, 16},    {402, 8, 24},     {426, 9, 76},
        {502, 10, 56},  {558, 11, 16},   {574, 12, 44},   {618, 13, 92},    {710, 14, 108},
        {818, 15, 364}, {1182, 16, 328}, {1510, 17, 8},   {1518, 18, 40},   {1558, 19, 65},
        {1623, 20, 12}, {1635, 21, 18},  {1653, 22, 75},  {1728, 23, 56},   {1784, 24, 72},
        {1856, 25, 32}, {1888, 26, 8},   {1896, 27, 216}, {2112, 0xFFFF, 8}};
    ASSERT_EQ(nd.options.size(), expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i) {
        EXPECT_EQ(nd.options[i].offset, expected[i][0]) << i;
        EXPECT_EQ(nd.options[i].tag, expected[i][1]) << i;
        EXPECT_EQ(nd.options[i].size, expected[i][2]) << i;
    }
    EXPECT_EQ(nd.options.overflow(), 0U);
    EXPECT_TRUE(nd.skipped.empty());
    EXPECT_EQ(nd.checksum, 46179U);
    EXPECT_EQ(nd.checksum_offset, 2112U);
    EXPECT_EQ(nd.trailing_bytes, 0U);
    // Every option of §3.5 is present; tag 27 went to gps (216 B), not zimmu_3000.
    layout::for_each_option_type([&]<class T>(std::type_identity<T>) {
        const bool present = (nd.*layout::Spec<T>::member).has_value();
        const bool want = !std::is_same_v<T, Zimmu3000>;
        EXPECT_EQ(present, want) << layout::Spec<T>::name;
    });
}

TEST(NavdataFull, DemoTimeRawPhys) {
    const Navdata nd = parse_ok(read_fixture(test::kNavdataFull));
    const Demo& d = nd.demo.value();
    EXPECT_EQ(d.ctrl_state.raw, 0x00020000U);
    EXPECT_EQ(d.ctrl_state.major(), 2);
    EXPECT_EQ(d.ctrl_state.minor(), 0);
    EXPECT_EQ(ctrl_major_name(d.ctrl_state.major()), "CTRL_LANDED");
    EXPECT_EQ(ctrl_minor_name(d.ctrl_state.major(), d.ctrl_state.minor()), std::nullopt);
    EXPECT_EQ(d.vbat_flying_percentage, 50U);
    EXPECT_EQ(d.theta_mdeg, 2974.0f);
    EXPECT_EQ(d.phi_mdeg, 550.0f);
    EXPECT_EQ(d.psi_mdeg, 1933.0f);
    EXPECT_EQ(d.altitude_mm, 0);
    EXPECT_EQ(d.vx_mm_s, f(0.0585307739675045));
    EXPECT_EQ(d.vy_mm_s, f(-0.8817979097366333));
    EXPECT_EQ(d.vz_mm_s, 0.0f);
    EXPECT_EQ(d.num_frames, 0U);
    EXPECT_EQ(d.detection_camera_type, 3U);
    EXPECT_EQ(d.drone_camera_trans, (F3{0, 0, -243}));

    const DroneTime t = nd.time.value().time;
    EXPECT_EQ(t.raw, 0x2D4EF0B5U);
    EXPECT_EQ(t.seconds(), 362U);
    EXPECT_EQ(t.microseconds(), 979125U);
    EXPECT_EQ(t.total_us(), 362979125);
    EXPECT_DOUBLE_EQ(t.total_s(), 362.979125);

    const RawMeasures& r = nd.raw_measures.value();
    EXPECT_EQ(r.raw_accs, (std::array<std::uint16_t, 3>{2040, 2036, 2528}));
    EXPECT_EQ(r.raw_gyros, (std::array<std::int16_t, 3>{-23, 15, 0}));
    EXPECT_EQ(r.raw_gyros_110, (std::array<std::int16_t, 2>{0, 0}));
    EXPECT_EQ(r.vbat_raw_mv, 11686U);
    EXPECT_EQ(r.us_debut_echo, 0);
    EXPECT_EQ(r.us_fin_echo, 0);
    EXPECT_EQ(r.us_association_echo, 3758);
    EXPECT_EQ(r.us_distance_echo, 0);
    EXPECT_EQ(r.us_courbe_temps, 21423);
    EXPECT_EQ(r.us_courbe_valeur, 0);
    EXPECT_EQ(r.us_courbe_ref, 120);
    EXPECT_EQ(r.flag_echo_ini, 1);
    EXPECT_EQ(r.nb_echo, 1);
    EXPECT_EQ(r.sum_echo, 3539193U);
    EXPECT_EQ(r.alt_temp_raw_mm, 243);
    EXPECT_EQ(r.gradient, 41);

    const PhysMeasures& p = nd.phys_measures.value();
    EXPECT_EQ(p.accs_temp, f(45.309303283691406));
    EXPECT_EQ(p.gyro_temp, 55738);
    EXPECT_EQ(p.phys_accs_mg, (F3{f(80.2970962524414), f(-33.318603515625), f(-942.5283203125)}));
    EXPECT_EQ(p.phys_gyros_deg_s,
              (F3{f(-0.11236488074064255), f(0.06872134655714035), f(0.06200997903943062)}));
    EXPECT_EQ(p.alim3V3, 0U);
    EXPECT_EQ(p.vrefEpson, 0U);
    EXPECT_EQ(p.vrefIDG, 0U);
}

TEST(NavdataFull, ControlAndVisionOptions) {
    const Navdata nd = parse_ok(read_fixture(test::kNavdataFull));
    EXPECT_EQ(nd.gyros_offsets.value().offset_g,
              (F3{f(-0.5329172611236572), f(0.1788240224123001), 0}));
    EXPECT_EQ(nd.euler_angles.value().theta_a, 4866.0f);
    EXPECT_EQ(nd.euler_angles.value().phi_a, 2024.0f);
    EXPECT_EQ(nd.references.value().ref_theta_mdeg, 0);
    EXPECT_EQ(nd.references.value().ui_seq, 0);
    EXPECT_EQ(nd.rc_references.value().rc_ref_gaz, 0);
    const Trims& tr = nd.trims.value();
    EXPECT_EQ(tr.angular_rates_trim_r, 0.0f);
    EXPECT_EQ(tr.euler_angles_trim_theta, f(3028.916015625));
    EXPECT_EQ(tr.euler_angles_trim_phi, f(1544.318359375));

    const Pwm& pw = nd.pwm.value();
    EXPECT_EQ(pw.motor, (std::array<std::uint8_t, 4>{0, 0, 0, 0}));
    EXPECT_EQ(pw.sat_motor, (std::array<std::uint8_t, 4>{255, 255, 255, 255}));
    EXPECT_EQ(pw.current_motor_ma, (std::array<std::uint16_t, 4>{0, 0, 0, 0}));
    EXPECT_EQ(pw.altitude_der, 0.0f);

    const Altitude& a = nd.altitude.value();
    EXPECT_EQ(a.altitude_vision_mm, 243);
    EXPECT_EQ(a.altitude_vz_mm_s, 0.0f);
    EXPECT_EQ(a.altitude_ref_mm, 0);
    EXPECT_EQ(a.altitude_raw_mm, 243);
    EXPECT_EQ(a.est_state, 0U);

    const VisionRaw& vr = nd.vision_raw.value();
    EXPECT_EQ(vr.vision_tx_raw, f(1.3266397714614868));
    EXPECT_EQ(vr.vision_ty_raw, f(-0.7230937480926514));
    EXPECT_EQ(vr.vision_tz_raw, 0.0f);

    const Vision& v = nd.vision.value();
    EXPECT_EQ(v.vision_state, 2U);
    EXPECT_EQ(v.vision_misc, 0);
    EXPECT_EQ(v.theta_capture, f(0.05190306529402733));
    EXPECT_EQ(v.phi_capture, f(0.009620788507163525));
    EXPECT_EQ(v.psi_capture, f(0.033727407455444336));
    EXPECT_EQ(v.altitude_capture, 243);
    EXPECT_EQ(v.time_capture, 362969U);
    EXPECT_EQ(v.body_v_mm_s,
              (F3{f(0.05845191329717636), f(-0.8817280530929565), f(0.011505687609314919)}));
    EXPECT_EQ(v.gold_x, 0.0f);

    EXPECT_EQ(nd.vision_of.value().of_dx, (std::array<float, 5>{}));
    EXPECT_EQ(nd.vision_perf.value().time_custom, (std::array<float, 20>{}));
    EXPECT_EQ(nd.trackers_send.value().locked, (std::array<std::int32_t, 30>{}));
    EXPECT_EQ(nd.vision_detect.value().nb_detected, 0U);
    EXPECT_EQ(nd.adc_data_frame.value().data_frame, (std::array<std::uint8_t, 32>{}));
    EXPECT_EQ(nd.games.value().double_tap_counter, 0U);
    EXPECT_EQ(nd.hdvideo_stream.value().hdvideo_state, 0U);
}

TEST(NavdataFull, SensorsWifiAndGps) {
    const Navdata nd = parse_ok(read_fixture(test::kNavdataFull));
    EXPECT_EQ(nd.watchdog.value().watchdog, 4822);
    const VideoStream& vs = nd.video_stream.value();
    EXPECT_EQ(vs.quant, 0);
    EXPECT_EQ(vs.frame_size_bytes, 4597U);
    EXPECT_EQ(vs.frame_number, 46105U);
    EXPECT_EQ(vs.atcmd_ref_seq, 0U);
    EXPECT_EQ(vs.fifo_queue_level, 0U);

    const PressureRaw& pr = nd.pressure_raw.value();
    EXPECT_EQ(pr.up, 39148);
    EXPECT_EQ(pr.ut, 32556);
    EXPECT_EQ(pr.Temperature_meas_0_1C, 435);
    EXPECT_EQ(pr.Pression_meas_Pa, 101586);

    const Magneto& m = nd.magneto.value();
    EXPECT_EQ(m.mx, 30);
    EXPECT_EQ(m.my, -56);
    EXPECT_EQ(m.mz, 80);
    EXPECT_EQ(m.magneto_raw_mG, (F3{189, f(-100.8984375), f(-278.4375)}));
    EXPECT_EQ(m.magneto_rectified_mG,
              (F3{f(145.08058166503906), f(-84.93736267089844), f(-287.18157958984375)}));
    EXPECT_EQ(m.magneto_offset_mG, (F3{f(29.21237564086914), f(-13.282999038696289), 0}));
    EXPECT_EQ(m.heading_unwrapped, 0.0f);
    EXPECT_EQ(m.heading_gyro_unwrapped, f(0.00041322660399600863));
    EXPECT_EQ(m.heading_fusion_unwrapped_deg, f(1.933355689048767));
    EXPECT_EQ(m.magneto_calibration_ok, 1);
    EXPECT_EQ(m.magneto_state, 2U);
    EXPECT_EQ(m.magneto_radius, f(387.31146240234375));
    EXPECT_EQ(m.error_mean, f(-211.51361083984375));
    EXPECT_EQ(m.error_var, f(79.3671875));

    const WindSpeed& w = nd.wind_speed.value();
    EXPECT_EQ(w.wind_speed_m_s, 0.0f);
    EXPECT_EQ(w.wind_angle, 0.0f);
    EXPECT_EQ(w.state_x, (std::array<float, 6>{f(0.05845191329717636), f(-0.8817280530929565), 0, 0,
                                               f(305.5962829589844), f(-236.80516052246094)}));
    EXPECT_EQ(w.magneto_debug, (F3{0, 0, 0}));

    const KalmanPressure& k = nd.kalman_pressure.value();
    EXPECT_EQ(k.offset_pressure, 101580.0f);
    EXPECT_EQ(k.est_z, 0.0f);
    EXPECT_EQ(k.cov_alt, f(0.0005193915567360818));
    EXPECT_EQ(k.cov_PWM, f(0.6806257367134094));
    EXPECT_EQ(k.cov_vitesse, f(0.025059189647436142));
    EXPECT_EQ(k.bool_effet_sol, 1);  // a 4-byte bool_t: a 1-byte read would shift what follows
    EXPECT_EQ(k.somme_inno, 0.0f);
    EXPECT_EQ(k.flag_rejet_US, 0);
    EXPECT_EQ(k.Flag_multisinus_debut, 0);

    EXPECT_EQ(nd.wifi.value().link_quality, 0U);

    const Gps& g = nd.gps.value();
    EXPECT_DOUBLE_EQ(g.latitude_deg, 34.0905016);
    EXPECT_DOUBLE_EQ(g.longitude_deg, -118.2766877);
    EXPECT_DOUBLE_EQ(g.elevation_m, 122.64);
    EXPECT_DOUBLE_EQ(g.hdop, 1.0);
    EXPECT_EQ(g.data_available, 7);
    EXPECT_EQ(g.zero_validated, 1);
    EXPECT_EQ(g.wpt_validated, 0);
    EXPECT_DOUBLE_EQ(g.lat0_deg, 34.0905016);
    EXPECT_DOUBLE_EQ(g.lon0_deg, -118.2766877);
    EXPECT_DOUBLE_EQ(g.lat_fuse_deg, 34.0904833);
    EXPECT_DOUBLE_EQ(g.lon_fuse_deg, -118.2766982);
    EXPECT_EQ(g.gps_state, 1U);
    EXPECT_EQ(g.x_traj, 0.0f);
    EXPECT_EQ(g.phi_d, 0.0f);
    EXPECT_EQ(g.vdop, 0.0);
    EXPECT_EQ(g.pdop, 0.0);
    EXPECT_EQ(g.speed_m_s, f(0.10000000149011612));
    EXPECT_EQ(g.last_frame_timestamp, 0x00358237U);
    EXPECT_EQ(g.degree_deg, f(141.00999450683594));
    EXPECT_EQ(g.degree_mag, 0.0f);
    EXPECT_EQ(g.ehpe, f(8.260000228881836));
    EXPECT_EQ(g.ehve, f(0.429999977350235));
    EXPECT_EQ(g.c_n0, 28.0f);
    EXPECT_EQ(g.nb_satellites, 9U);
    const std::array<std::array<int, 2>, 12> ch = {{{10, 26},
                                                    {5, 21},
                                                    {8, 27},
                                                    {3, 17},
                                                    {13, 18},
                                                    {7, 32},
                                                    {9, 23},
                                                    {27, 9},
                                                    {19, 19},
                                                    {28, 29},
                                                    {30, 26},
                                                    {138, 0}}};
    for (std::size_t i = 0; i < ch.size(); ++i) {
        EXPECT_EQ(g.channels[i].sat, ch[i][0]) << i;
        EXPECT_EQ(g.channels[i].cn0, ch[i][1]) << i;
    }
    EXPECT_EQ(g.gps_plugged, 1);
    EXPECT_EQ(g.ephemeris_status, 73U);
    EXPECT_EQ(g.vx_traj, 0.0f);
    EXPECT_EQ(g.vy_traj, 0.0f);
    EXPECT_EQ(g.firmware_status, 1U);
}

TEST(NavdataFull, ToNavStateConvertsUnits) {
    const Navdata nd = parse_ok(read_fixture(test::kNavdataFull));
    const NavState s = to_nav_state(nd, 1'500'000'000);
    EXPECT_EQ(s.t_ns, 1'500'000'000);
    EXPECT_DOUBLE_EQ(s.pitch_deg, 2.974);
    EXPECT_DOUBLE_EQ(s.roll_deg, 0.55);
    EXPECT_DOUBLE_EQ(s.yaw_deg, 1.933);
    EXPECT_DOUBLE_EQ(s.vx_mps, static_cast<double>(f(0.0585307739675045)) / 1000.0);
    EXPECT_DOUBLE_EQ(s.vy_mps, static_cast<double>(f(-0.8817979097366333)) / 1000.0);
    EXPECT_EQ(s.vz_mps, 0.0);
    EXPECT_EQ(s.altitude_m, 0.0);
    EXPECT_EQ(s.battery_pct, 50.0);
    EXPECT_EQ(s.seq, 300711U);
    EXPECT_EQ(s.drone_state, 0x4F8000D0U);
    EXPECT_EQ(s.ctrl_state, 0x00020000U);
}

// ---- other captures (§7.3)
// ------------------------------------------------------------------------

TEST(Navdata2012, GoDecoderValuesAndZimmuTag27) {
    const auto bytes = read_fixture(test::kNavdata2012);
    ASSERT_EQ(bytes.size(), 1916U);
    const Navdata nd = parse_ok(bytes);
    EXPECT_EQ(nd.header.magic, 1432778632U);
    EXPECT_EQ(nd.header.drone_state.raw, 1333788880U);
    EXPECT_EQ(nd.header.sequence, 300711U);
    EXPECT_EQ(nd.header.vision_defined, 1U);
    EXPECT_EQ(nd.demo.value().ctrl_state.minor(), 0);  // GO FlyState
    EXPECT_EQ(nd.demo.value().ctrl_state.major(), 2);  // GO ControlState
    EXPECT_EQ(nd.demo.value().vbat_flying_percentage, 50U);
    EXPECT_EQ(nd.demo.value().altitude_mm, 0);
    EXPECT_EQ(nd.checksum, 36358U);
    ASSERT_TRUE(nd.zimmu_3000.has_value());
    EXPECT_EQ(nd.zimmu_3000->vzimmuLSB, 0);
    EXPECT_EQ(nd.zimmu_3000->vzfind, 0.0f);
    EXPECT_FALSE(nd.gps.has_value());
    EXPECT_TRUE(nd.skipped.empty());
    EXPECT_EQ(nd.options[nd.options.size() - 2].size, 12);
    // Same capture as the 2014 file before the GPS splice: same decoded pressure and time.
    EXPECT_EQ(nd.pressure_raw.value().Pression_meas_Pa, 101586);
    EXPECT_EQ(nd.time.value().time.raw, 0x2D4EF0B5U);
}

TEST(Navdata2013, Tag27Of480BytesIsReportedOpaque) {
    const Navdata nd = parse_ok(read_fixture(test::kNavdata2013));
    EXPECT_EQ(nd.checksum, 57639U);
    EXPECT_FALSE(nd.gps.has_value());
    EXPECT_FALSE(nd.zimmu_3000.has_value());
    ASSERT_EQ(nd.skipped.size(), 1U);
    EXPECT_EQ(nd.skipped[0].option.tag, 27);
    EXPECT_EQ(nd.skipped[0].option.size, 480);
    EXPECT_EQ(nd.skipped[0].option.offset, 1896U);
    EXPECT_EQ(nd.skipped[0].reason, SkipReason::OpaqueTag27);
    EXPECT_EQ(option_name(27, 480), "tag27_opaque");
    EXPECT_EQ(nd.checksum_offset, 2376U);
    EXPECT_TRUE(nd.wifi.has_value());  // the options before it still decode
}

TEST(NavdataDemoInflight, DemoModePacket) {
    const auto bytes = read_fixture(test::kNavdataDemo);
    ASSERT_EQ(bytes.size(), 500U);
    const Navdata nd = parse_ok(bytes);
    EXPECT_EQ(nd.header.drone_state.raw, 0x0F8004F5U);
    expect_state_bits(nd.header.drone_state, {0, 2, 4, 5, 6, 7, 10, 23, 24, 25, 26, 27});
    EXPECT_TRUE(nd.header.drone_state.fly());
    EXPECT_TRUE(nd.header.drone_state.navdata_demo());
    EXPECT_FALSE(nd.header.drone_state.com_watchdog());
    EXPECT_EQ(nd.header.sequence, 6069U);
    ASSERT_EQ(nd.options.size(), 3U);
    EXPECT_EQ(nd.options[0].tag, 0);
    EXPECT_EQ(nd.options[1].tag, 16);
    EXPECT_EQ(nd.options[2].tag, 0xFFFF);
    EXPECT_EQ(nd.checksum, 9187U);
    const Demo& d = nd.demo.value();
    EXPECT_EQ(d.ctrl_state.raw, 0x00030000U);
    EXPECT_EQ(ctrl_major_name(d.ctrl_state.major()), "CTRL_FLYING");
    EXPECT_EQ(ctrl_minor_name(d.ctrl_state.major(), d.ctrl_state.minor()), "OK");
    EXPECT_EQ(d.vbat_flying_percentage, 76U);
    EXPECT_EQ(d.theta_mdeg, -92.0f);
    EXPECT_EQ(d.phi_mdeg, -440.0f);
    EXPECT_EQ(d.psi_mdeg, 14668.0f);
    EXPECT_EQ(d.altitude_mm, 534);
    EXPECT_EQ(d.vx_mm_s, f(268.4826354980469));
    EXPECT_EQ(d.vy_mm_s, f(-195.2543487548828));
    EXPECT_EQ(d.vz_mm_s, 0.0f);
    EXPECT_EQ(d.detection_camera_type, 3U);
    EXPECT_EQ(nd.vision_detect.value().nb_detected, 0U);
    EXPECT_FALSE(nd.time.has_value());

    const NavState s = to_nav_state(nd, 0);
    EXPECT_DOUBLE_EQ(s.pitch_deg, -0.092);
    EXPECT_DOUBLE_EQ(s.roll_deg, -0.44);
    EXPECT_DOUBLE_EQ(s.yaw_deg, 14.668);
    EXPECT_DOUBLE_EQ(s.altitude_m, 0.534);
    EXPECT_DOUBLE_EQ(s.vx_mps, static_cast<double>(f(268.4826354980469)) / 1000.0);
    EXPECT_EQ(s.battery_pct, 76.0);
}

TEST(NavdataBootstrap, ForumHexBytes) {
    const std::vector<std::uint8_t> b = {0x88, 0x77, 0x66, 0x55, 0x10, 0x0C, 0x80, 0x4F,
                                         0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
                                         0xFF, 0xFF, 0x08, 0x00, 0xA6, 0x02, 0x00, 0x00};
    const Navdata nd = parse_ok(b);
    EXPECT_EQ(nd.header.drone_state.raw, 0x4F800C10U);
    expect_state_bits(nd.header.drone_state, {4, 10, 11, 23, 24, 25, 26, 27, 30});
    EXPECT_TRUE(nd.header.drone_state.navdata_bootstrap());
    EXPECT_EQ(nd.header.sequence, 1U);
    EXPECT_EQ(nd.header.vision_defined, 0U);
    EXPECT_EQ(nd.checksum, 678U);
    ASSERT_EQ(nd.options.size(), 1U);
    EXPECT_EQ(nd.options[0].tag, 0xFFFF);
    EXPECT_FALSE(nd.demo.has_value());
    const NavState s = to_nav_state(nd, 0);
    EXPECT_TRUE(std::isnan(s.pitch_deg));  // no demo: unknown, not 0
    EXPECT_TRUE(std::isnan(s.battery_pct));
    EXPECT_FALSE(s.ctrl_state.has_value());
    EXPECT_EQ(s.seq, 1U);
}

// ---- tables
// --------------------------------------------------------------------------------------

TEST(NavdataTables, CtrlStateNamesAreMajorSpecific) {
    EXPECT_EQ(ctrl_major_name(0), "CTRL_DEFAULT");
    EXPECT_EQ(ctrl_major_name(4), "CTRL_HOVERING");
    EXPECT_EQ(ctrl_major_name(9), "CTRL_TRANS_LOOPING");
    EXPECT_EQ(ctrl_major_name(10), std::nullopt);
    EXPECT_EQ(ctrl_minor_name(3, 6), "NO_VISION");
    EXPECT_EQ(ctrl_minor_name(3, 7), std::nullopt);
    EXPECT_EQ(ctrl_minor_name(4, 13), "DEMO");
    EXPECT_EQ(ctrl_minor_name(4, 6), "LOST_ALT");
    EXPECT_EQ(ctrl_minor_name(6, 1), "AUTO");
    EXPECT_EQ(ctrl_minor_name(7, 2), "YAW");
    EXPECT_EQ(ctrl_minor_name(8, 0), "CLOSED_LOOP");
    EXPECT_EQ(ctrl_minor_name(9, 2), "PLANIF_CTRL");
    EXPECT_EQ(ctrl_minor_name(2, 0), std::nullopt);  // LANDED has no minor table
    EXPECT_EQ(CtrlState::make(CtrlMajor::Hovering, 8).raw, 0x00040008U);
}

TEST(NavdataTables, DroneStateBitNames) {
    EXPECT_EQ(to_string(DroneStateBit::Fly), "FLY");
    EXPECT_EQ(to_string(DroneStateBit::NavdataBootstrap), "NAVDATA_BOOTSTRAP");
    EXPECT_EQ(to_string(DroneStateBit::MagnetoNeedsCalib), "MAGNETO_NEEDS_CALIB");
    EXPECT_EQ(to_string(DroneStateBit::Emergency), "EMERGENCY");
    EXPECT_EQ(static_cast<int>(DroneStateBit::Emergency), 31);
    DroneState s;
    s.set(DroneStateBit::Emergency, true);
    EXPECT_EQ(s.raw, 0x80000000U);
    EXPECT_TRUE(s.emergency());
}

TEST(NavdataTables, DroneTimeSplitsElevenAndTwentyOneBits) {
    EXPECT_EQ(DroneTime::make(362, 979125).raw, 0x2D4EF0B5U);
    const DroneTime t{0xFFFFFFFFU};
    EXPECT_EQ(t.seconds(), 2047U);
    EXPECT_EQ(t.microseconds(), 0x1FFFFFU);
}

// Each option's fields tile bytes [4, size) with no gap and no overlap, so decoding a block of
// the layout size never reads outside it and every byte is accounted for.
TEST(NavdataLayout, FieldsTileEveryOptionExactly) {
    layout::for_each_option_type([]<class T>(std::type_identity<T>) {
        using S = layout::Spec<T>;
        std::vector<std::pair<std::size_t, std::size_t>> spans;
        const T opt{};
        S::fields(opt, [&](std::size_t off, std::string_view, std::string_view, const auto& fld) {
            spans.emplace_back(off, layout::wire_size_v<std::remove_cvref_t<decltype(fld)>>);
        });
        std::size_t at = 4;
        for (const auto& [off, n] : spans) {
            EXPECT_EQ(off, at) << S::name;
            at = off + n;
        }
        EXPECT_EQ(at, S::size) << S::name;
    });
}

// ---- malformed input
// ------------------------------------------------------------------------------

TEST(NavdataErrors, IncrementedByte23IsAChecksumError) {
    auto b = read_fixture(test::kNavdataFull);
    ++b[23];
    const auto r = parse_navdata(b);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, NavdataErrc::BadChecksum);
    EXPECT_EQ(r.error().expected, 46180U);
    EXPECT_EQ(r.error().got, 46179U);
}

TEST(NavdataErrors, IncrementedByte20ReportsExpectedAndGot) {
    auto b = read_fixture(test::kNavdata2012);
    ++b[20];
    const auto r = parse_navdata(b);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, NavdataErrc::BadChecksum);
    EXPECT_EQ(r.error().expected, 36359U);
    EXPECT_EQ(r.error().got, 36358U);
    EXPECT_EQ(to_string(r.error()), "bad checksum, expected: 36359, got: 36358");
}

TEST(NavdataErrors, DroppedChecksumBlockIsMissingChecksum) {
    auto b = read_fixture(test::kNavdataFull);
    ASSERT_GT(b.size(), 8U);
    b.erase(b.end() - 8, b.end());  // (resize() here trips GCC 12's -Wstringop-overflow under ASan)
    const auto r = parse_navdata(b);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, NavdataErrc::MissingChecksum);
    EXPECT_EQ(r.error().offset, 2112U);
}

TEST(NavdataErrors, FourBytesIsABadHeader) {
    const std::vector<std::uint8_t> b = {0x01, 0x02, 0x03, 0x04};
    const auto r = parse_navdata(b);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, NavdataErrc::BadMagic);
    EXPECT_EQ(r.error().expected, 0x55667788U);
    EXPECT_EQ(r.error().got, 0x04030201U);
    EXPECT_EQ(to_string(r.error()), "bad magic, expected: 0x55667788, got: 0x04030201");
}

TEST(NavdataErrors, ShortHeaders) {
    for (std::size_t n : {0U, 3U}) {
        const std::vector<std::uint8_t> b(n, 0x88);
        const auto r = parse_navdata(b);
        ASSERT_FALSE(r);
        EXPECT_EQ(r.error().code, NavdataErrc::TruncatedHeader) << n;
    }
    const std::vector<std::uint8_t> magic_only = {0x88, 0x77, 0x66, 0x55, 0, 0, 0, 0};
    const auto r = parse_navdata(magic_only);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, NavdataErrc::TruncatedHeader);
    EXPECT_EQ(r.error().got, 8U);
}

std::vector<std::uint8_t> bootstrap_header() {
    return {0x88, 0x77, 0x66, 0x55, 0x10, 0x0C, 0x80, 0x4F, 1, 0, 0, 0, 0, 0, 0, 0};
}

TEST(NavdataErrors, OptionSizePastEnd) {
    auto b = bootstrap_header();
    b.insert(b.end(), {0x01, 0x00, 0x08, 0x00, 0xAA, 0xBB});  // time, size 8, only 6 bytes
    const auto r = parse_navdata(b);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, NavdataErrc::OptionPastEnd);
    EXPECT_EQ(r.error().offset, 16U);
    EXPECT_EQ(r.error().tag, 1);
    EXPECT_EQ(r.error().got, 8U);
    EXPECT_EQ(r.error().expected, 6U);
}

TEST(NavdataErrors, ZeroAndTinySizesStopInsteadOfLooping) {
    for (std::uint8_t size : {0, 1, 3}) {
        auto b = bootstrap_header();
        b.insert(b.end(), {0x05, 0x00, size, 0x00, 0, 0, 0, 0, 0xFF, 0xFF, 8, 0, 0, 0, 0, 0});
        const auto r = parse_navdata(b);
        ASSERT_FALSE(r);
        EXPECT_EQ(r.error().code, NavdataErrc::OptionTooSmall) << int{size};
        EXPECT_EQ(r.error().got, size);
    }
    auto b = bootstrap_header();
    b.insert(b.end(), {0xFF, 0xFF, 0x04, 0x00});  // a cks block without its value
    const auto r = parse_navdata(b);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, NavdataErrc::OptionTooSmall);
    EXPECT_EQ(r.error().expected, 8U);
}

TEST(NavdataErrors, TruncatedOptionHeader) {
    auto b = bootstrap_header();
    b.insert(b.end(), {0xFF, 0xFF});
    const auto r = parse_navdata(b);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, NavdataErrc::TruncatedOptionHeader);
    EXPECT_EQ(r.error().got, 2U);
}

// Puts a cks block with the right sum after `b`.
void append_cks(std::vector<std::uint8_t>& b) {
    const std::uint32_t sum = navdata_checksum(b);
    b.insert(b.end(),
             {0xFF, 0xFF, 8, 0, static_cast<std::uint8_t>(sum), static_cast<std::uint8_t>(sum >> 8),
              static_cast<std::uint8_t>(sum >> 16), static_cast<std::uint8_t>(sum >> 24)});
}

TEST(NavdataSkips, UnknownShortDuplicateAndLargerOptions) {
    auto b = bootstrap_header();
    b.insert(b.end(), {0x63, 0x00, 0x06, 0x00, 0xAB, 0xCD});                    // tag 99, unknown
    b.insert(b.end(), {0x11, 0x00, 0x06, 0x00, 0x01, 0x02});                    // watchdog, 6 < 8
    b.insert(b.end(), {0x11, 0x00, 0x0A, 0x00, 0xD6, 0x12, 0, 0, 0xEE, 0xEE});  // watchdog 10 B
    b.insert(b.end(), {0x11, 0x00, 0x08, 0x00, 0x01, 0, 0, 0});  // duplicate watchdog
    append_cks(b);
    b.push_back(0x42);  // a trailing byte after cks
    const Navdata nd = parse_ok(b);
    ASSERT_TRUE(nd.watchdog.has_value());
    EXPECT_EQ(nd.watchdog->watchdog, 4822);  // the grown block decoded by its known prefix
    ASSERT_EQ(nd.skipped.size(), 3U);
    EXPECT_EQ(nd.skipped[0].reason, SkipReason::UnknownTag);
    EXPECT_EQ(nd.skipped[0].option.tag, 99);
    EXPECT_EQ(nd.skipped[1].reason, SkipReason::TooShort);
    EXPECT_EQ(nd.skipped[2].reason, SkipReason::Duplicate);
    EXPECT_EQ(nd.options.size(), 5U);
    EXPECT_EQ(nd.trailing_bytes, 1U);
}

TEST(NavdataFuzz, EveryTruncationOfEveryCaptureFailsCleanly) {
    for (const char* name :
         {test::kNavdataFull, test::kNavdata2012, test::kNavdata2013, test::kNavdataDemo}) {
        const auto full = read_fixture(name);
        for (std::size_t n = 0; n < full.size(); ++n) {
            // A copy of exactly n bytes so ASan catches any read past the end.
            const std::vector<std::uint8_t> cut(full.begin(), full.begin() + static_cast<long>(n));
            const auto r = parse_navdata(cut);
            EXPECT_FALSE(r) << name << " cut to " << n;
        }
    }
}

TEST(NavdataFuzz, RandomBytesAndBitFlipsNeverCrash) {
    std::mt19937 rng(12345);
    std::uniform_int_distribution<int> byte(0, 255);
    std::size_t ok = 0;
    for (int i = 0; i < 2000; ++i) {
        std::vector<std::uint8_t> b(static_cast<std::size_t>(byte(rng)) * 4);
        for (auto& x : b) x = static_cast<std::uint8_t>(byte(rng));
        if (b.size() >= 4 && i % 2 == 0) {  // half of them with a valid magic to get further
            b[0] = 0x88, b[1] = 0x77, b[2] = 0x66, b[3] = 0x55;
        }
        ok += parse_navdata(b).has_value() ? 1 : 0;
    }
    EXPECT_LT(ok, 20U);  // random bytes essentially never carry a valid checksum
    const auto full = read_fixture(test::kNavdataFull);
    std::size_t rejected = 0;
    for (std::size_t bit = 0; bit < full.size() * 8; bit += 3) {
        auto b = full;
        b[bit / 8] = static_cast<std::uint8_t>(b[bit / 8] ^ (1U << (bit % 8)));
        rejected += parse_navdata(b).has_value() ? 0 : 1;
    }
    // Every single-bit flip changes either the framing or the byte sum.
    EXPECT_EQ(rejected, (full.size() * 8 + 2) / 3);
}

}  // namespace
}  // namespace gs::protocol::navdata
