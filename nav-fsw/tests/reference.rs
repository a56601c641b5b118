//! docs/reference/flight-parameters.md is written from the parameter table: this test renders
//! it and fails when the committed file differs. `NAV_BLESS=1 cargo test -p nav-fsw --test
//! reference` writes it. The page is the default build's table: a build without the
//! feature `gravity-field` narrows the gravity parameters' ranges and has no page of its own.
#![cfg(feature = "gravity-field")]

use nav_fsw::config::{FswConfig, Number, Param, COMPANIONS};
use nav_fsw::ConfigField;

/// The page, from the table.
fn render() -> String {
    let mut page = String::from(
        "# Flight parameters\n\n\
         Generated from the parameter table (`nav-fsw/src/config/parameters.rs`) by \
         `NAV_BLESS=1 cargo test -p nav-fsw --test reference`; the test fails when this file \
         differs from the table. Do not edit it by hand.\n\n\
         Every parameter of the flight software's configuration (`FswConfig`): its path, unit, \
         default (`mission`: given by the mission or the scenario), the range \
         `FswConfig::validate` accepts (a value outside is refused naming the path, the range \
         and the unit) and why, and its word in the replay setup (`-`: not carried; the \
         replay takes the default). nav-sim's `[filter]` keys are checked by these same \
         rules.\n\n",
    );
    let initial = nav_fsw::replay::INITIAL_NAVIGATION_WORDS;
    page.push_str(&format!(
        "The replay setup has {} words: word 0 is the magic `NAVSETUP`, words {} to {} the \
         initial navigation solution (attitude `w x y z`, position, velocity, time), every \
         other word a parameter's.\n\n\
         | path | unit | default | range | word | why |\n|---|---|---|---|---|---|\n",
        nav_fsw::replay::SETUP_WORDS,
        initial.start,
        initial.end - 1
    ));
    for param in Param::ALL {
        let range = param.range();
        let default = match param.default_value() {
            None => "mission".to_string(),
            Some(value) if !range.choices.is_empty() => {
                let index = value as usize;
                range.choices.get(index).copied().unwrap_or("?").to_string()
            }
            Some(value) => Number(value).to_string(),
        };
        let word = param
            .word()
            .map_or("-".to_string(), |word| word.to_string());
        let unit = if param.unit().is_empty() {
            "-"
        } else {
            param.unit()
        };
        page.push_str(&format!(
            "| `{}` | {unit} | {default} | {range} | {word} | {} |\n",
            param.path(),
            param.why().replace('|', "/")
        ));
    }
    page.push_str("\n## Parameters that go together\n\nWhen the first is on (not 0), the second must be too:\n\n");
    for (on, off) in COMPANIONS {
        page.push_str(&format!("- `{}` needs `{}`\n", on.path(), off.path()));
    }
    page.push_str("\n## Rules between values\n\n");
    for field in [
        ConfigField::LaunchSite,
        ConfigField::SensorFrames,
        ConfigField::StarMounting,
        ConfigField::StarSecondHead,
        ConfigField::MaxLatency,
        ConfigField::FutureTolerance,
        ConfigField::Gravity,
        ConfigField::CalibrationObservabilityTable,
    ] {
        page.push_str(&format!("- `{}` {}\n", field.key(), field.rule()));
    }
    page
}

#[test]
fn the_flight_parameter_reference_is_the_table() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../docs/reference/flight-parameters.md");
    let page = render();
    if std::env::var_os("NAV_BLESS").is_some() {
        std::fs::write(&path, &page).unwrap();
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == page,
        "{} differs from the parameter table: run NAV_BLESS=1 cargo test -p nav-fsw --test \
         reference",
        path.display()
    );
    // Every parameter is on the page, and the page names what the defaults are.
    let defaults = FswConfig::paper_defaults(
        nav_fsw::nav_core::frames::LaunchSite {
            latitude_rad: 0.0,
            longitude_rad: 0.0,
            height_m: 0.0,
            azimuth_rad: 0.0,
            earth_axis_ecef: [0.0, 0.0, 1.0],
        },
        nav_fsw::sensor_frames::SensorFrames::ALIGNED,
    );
    for param in Param::ALL {
        assert!(page.contains(&format!("| `{}` |", param.path())));
        if let Some(value) = param.default_value() {
            assert_eq!(value.to_bits(), param.value(&defaults).to_bits());
        }
    }
}

/// docs/reference/telemetry-packets.md, from the packet declaration.
fn render_packets() -> String {
    use nav_fsw::replay::OUTPUT_FIELD_NAMES;
    use nav_fsw::telemetry_packets::{
        WordType, CRC_BYTES, MAX_FRAME_PACKET_BYTES, PACKETS, PRIMARY_HEADER_BYTES,
        SECONDARY_HEADER_BYTES,
    };
    let mut page = String::from(
        "# Telemetry packets\n\n\
         Generated from the packet declaration (`nav-fsw/src/telemetry_packets/declaration.rs`) \
         by `NAV_BLESS=1 cargo test -p nav-fsw --test reference`; the test fails when this file \
         differs from the declaration. Do not edit it by hand.\n\n\
         Every frame's output record (the replay's, nav-fsw `replay::OUTPUT_FIELD_NAMES`) as \
         CCSDS Space Packets (CCSDS 133.0-B-2), one APID per kind, each kind every N frames \
         (`telemetry_packets::PacketRates`: sent in the frames whose counter is a multiple of \
         N). Every field is big-endian; a word is 8 bytes, `f64` (IEEE-754 bits) or `u64`.\n\n\
         | bytes | field |\n|---|---|\n",
    );
    let secondary_end = PRIMARY_HEADER_BYTES + SECONDARY_HEADER_BYTES;
    page.push_str(&format!(
        "| 0..{PRIMARY_HEADER_BYTES} | primary header: version 0, type 0 (telemetry), \
         secondary header flag 1, APID (11 bits); sequence flags `11` (unsegmented), \
         sequence count (14 bits, per APID, wraps); data length = packet bytes − 7 |\n\
         | {PRIMARY_HEADER_BYTES}..{secondary_end} | secondary header: `frame` (`u64`), \
         `time_s` (`f64`, navigation time) |\n\
         | {secondary_end}.. | the kind's words, in the order below |\n\
         | last {CRC_BYTES} | CRC-16/CCITT-FALSE (polynomial `0x1021`, initial `0xFFFF`) of \
         every byte before it |\n\n\
         One frame's packets, every kind due, take {MAX_FRAME_PACKET_BYTES} bytes.\n\n\
         | APID | kind | bytes | content |\n|---|---|---|---|\n"
    ));
    for packet in &PACKETS {
        page.push_str(&format!(
            "| `{:#05x}` | `{}` | {} | {} |\n",
            packet.apid,
            packet.name,
            packet.packet_bytes(),
            packet
                .purpose
                .split_whitespace()
                .collect::<Vec<_>>()
                .join(" ")
        ));
    }
    for packet in &PACKETS {
        page.push_str(&format!(
            "\n## `{}` (APID `{:#05x}`)\n\n| byte | word | type |\n|---|---|---|\n",
            packet.name, packet.apid
        ));
        let mut byte = secondary_end;
        for span in packet.words {
            for index in span.indices() {
                let word_type = match span.word_type {
                    WordType::Float => "f64",
                    WordType::Unsigned => "u64",
                };
                page.push_str(&format!(
                    "| {byte} | `{}` | {word_type} |\n",
                    OUTPUT_FIELD_NAMES[index]
                ));
                byte += 8;
            }
        }
    }
    page
}

#[test]
fn the_telemetry_packet_reference_is_the_declaration() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../docs/reference/telemetry-packets.md");
    let page = render_packets();
    if std::env::var_os("NAV_BLESS").is_some() {
        std::fs::write(&path, &page).unwrap();
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == page,
        "{} differs from the packet declaration: run NAV_BLESS=1 cargo test -p nav-fsw \
         --test reference",
        path.display()
    );
    // Every output word is on the page.
    for name in nav_fsw::replay::OUTPUT_FIELD_NAMES {
        assert!(
            page.contains(&format!("`{name}`")),
            "{name} is not on the page"
        );
    }
}
