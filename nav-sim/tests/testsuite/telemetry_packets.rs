//! Telemetry packets on the host: `nav-sim replay --packets` decoded by `nav-sim telemetry
//! decode` gives the replay's output records word for word, packets at slower rates leave
//! their words empty in the frames they skip, the packets read as standard space packets with
//! their CRC by an independent implementation (`spacepackets`), and a corrupt stream is
//! refused naming the packet and what is wrong.

use crate::cli::{assert_failed_saying, nav_sim, short_scenario};
use crate::common;

use nav_fsw::replay::{OUTPUT_FIELD_NAMES, OUTPUT_WORDS};
use nav_fsw::telemetry_packets::{PacketKind, PacketRates, PACKETS};
use nav_sim::harness::target_replay::{run_records_on_host, FRAME_WORDS};
use nav_sim::logs::telemetry_packets::{decode_stream, encode_frames, PacketStreamError};
use nav_sim::setup::fsw::replay_setup;

/// The output words of the first `frames` frames of the short test flight (the host run the
/// QEMU replays compare with), with their cost words.
fn host_frames(frames: u64) -> Vec<u64> {
    let scenario = common::short_scenario();
    let log = nav_sim::logs::sensor_log::simulated_records(&scenario, frames).unwrap();
    run_records_on_host(&replay_setup(&scenario).unwrap(), log).unwrap()
}

#[test]
fn host_packets_decode_to_the_replay_records_word_for_word() {
    let directory = tempfile::tempdir().unwrap();
    let dir = directory.path();
    short_scenario(dir, "short.toml", &[]);
    assert!(nav_sim(dir, &["log", "short.toml", "--out", "log.csv"])
        .status
        .success());
    let replay = nav_sim(
        dir,
        &[
            "replay",
            "log.csv",
            "--scenario",
            "short.toml",
            "--packets",
            "packets.bin",
            "--records",
            "records.csv",
        ],
    );
    assert!(replay.status.success(), "{replay:?}");
    let decode = nav_sim(
        dir,
        &[
            "telemetry",
            "decode",
            "--input",
            "packets.bin",
            "--output",
            "decoded.csv",
        ],
    );
    assert!(decode.status.success(), "{decode:?}");
    let records = std::fs::read_to_string(dir.join("records.csv")).unwrap();
    let decoded = std::fs::read_to_string(dir.join("decoded.csv")).unwrap();
    // The 2 s flight: 1,000 frames and the header.
    assert_eq!(records.lines().count(), 1_001);
    assert_eq!(
        records.lines().next().unwrap(),
        OUTPUT_FIELD_NAMES.join(",")
    );
    assert!(
        decoded == records,
        "the decoded packets differ from the records"
    );
    // Every kind in every frame.
    let packets = std::fs::read(dir.join("packets.bin")).unwrap();
    let frame_bytes: usize = PACKETS.iter().map(|p| p.packet_bytes()).sum();
    assert_eq!(packets.len(), 1_000 * frame_bytes);

    std::fs::write(dir.join("corrupt.bin"), corrupt_byte(&packets, 5_000)).unwrap();
    let refused = nav_sim(
        dir,
        &[
            "telemetry",
            "decode",
            "--input",
            "corrupt.bin",
            "--output",
            "c.csv",
        ],
    );
    assert_failed_saying(&refused, "CRC");
    assert!(!dir.join("c.csv").exists());
}

/// The packets of the host run decode to its output words, bit for bit, NaN words included.
#[test]
fn packets_carry_every_output_word_bit_for_bit() {
    let host = host_frames(500);
    let stream = encode_frames(&host, 1, PacketRates::EVERY_FRAME).unwrap();
    let decoded = decode_stream(&stream).unwrap();
    assert_eq!(decoded.len(), 500);
    for (frame, words) in decoded.iter().zip(host.chunks_exact(FRAME_WORDS)) {
        let received: Vec<u64> = frame.iter().map(|word| word.unwrap()).collect();
        assert_eq!(received, words[..OUTPUT_WORDS]);
    }
    // Every packet is a standard telemetry space packet with a valid CRC-16 (spacepackets'
    // own reader and check).
    let mut offset = 0;
    while offset < stream.len() {
        let packet = spacepackets::CcsdsPacketReader::new_with_checksum(&stream[offset..]).unwrap();
        assert_eq!(packet.packet_type(), spacepackets::PacketType::Tm);
        assert!(PacketKind::of_apid(packet.apid().value()).is_some());
        offset += packet.packet_data().len() + 6 + 2;
    }
}

#[test]
fn a_kind_at_a_slower_rate_is_empty_in_the_frames_it_skips() {
    let host = host_frames(100);
    let mut rates = PacketRates::EVERY_FRAME;
    rates.set(PacketKind::Health, 25).unwrap();
    rates.set(PacketKind::Calibration, 10).unwrap();
    let decoded = decode_stream(&encode_frames(&host, 1, rates).unwrap()).unwrap();
    assert_eq!(decoded.len(), 100);
    let index = |name: &str| OUTPUT_FIELD_NAMES.iter().position(|n| *n == name).unwrap();
    let (imu_missing, gyro_bias, position) = (
        index("imu_missing"),
        index("gyro_bias_x"),
        index("position_x_m"),
    );
    for (frame, words) in decoded.iter().zip(host.chunks_exact(FRAME_WORDS)) {
        let counter = words[0];
        assert_eq!(frame[0], Some(counter));
        assert_eq!(frame[position], Some(words[position]));
        let expect = |every: u64, word: usize| (counter % every == 0).then_some(words[word]);
        assert_eq!(
            frame[imu_missing],
            expect(25, imu_missing),
            "frame {counter}"
        );
        assert_eq!(frame[gyro_bias], expect(10, gyro_bias), "frame {counter}");
    }
    assert_eq!(
        decoded.iter().filter(|f| f[gyro_bias].is_some()).count(),
        10
    );
}

/// A command executed or refused steps its counter in the health packet of the next frame,
/// decoded on the ground: frame 10 follows an accepted command, frame 20 a refused one
/// (`SaveCalibration` without a calibration store).
#[test]
fn commands_accepted_and_refused_show_in_the_decoded_health_packets() {
    use nav_fsw::replay::{output_words, FrameAssembler};
    use nav_fsw::scheduler::{Command, NavigationComputer};
    let scenario = common::short_scenario();
    let setup = replay_setup(&scenario).unwrap();
    let mut computer = NavigationComputer::new(setup.config(), setup.initial).unwrap();
    let mut assembler = FrameAssembler::new(setup.frame_grid()).unwrap();
    let mut records = Vec::new();
    for record in nav_sim::logs::sensor_log::simulated_records(&scenario, 30).unwrap() {
        assembler.push(&record).unwrap();
        while let Some(mut ports) = assembler.next_frame() {
            let frames_run = records.len() / OUTPUT_WORDS;
            if frames_run == 10 {
                computer.command(Command::ClearSensorFaults).unwrap();
            }
            if frames_run == 20 {
                assert!(computer.command(Command::SaveCalibration).is_err());
            }
            let telemetry = ports.run(&mut computer);
            records.extend(output_words(&telemetry, &computer, &assembler.counts()));
        }
    }
    let decoded =
        decode_stream(&encode_frames(&records, 0, PacketRates::EVERY_FRAME).unwrap()).unwrap();
    assert!(decoded.len() >= 25, "{} frames", decoded.len());
    let index = |name: &str| OUTPUT_FIELD_NAMES.iter().position(|n| *n == name).unwrap();
    let health = PacketKind::Health.declaration();
    for name in ["commands_accepted", "commands_refused"] {
        assert!(health
            .words
            .iter()
            .any(|span| span.indices().contains(&index(name))));
    }
    let (accepted, refused) = (index("commands_accepted"), index("commands_refused"));
    for (frame, words) in decoded.iter().enumerate() {
        let expected = (u64::from(frame >= 10), u64::from(frame >= 20));
        assert_eq!(
            (words[accepted], words[refused]),
            (Some(expected.0), Some(expected.1)),
            "frame {frame}"
        );
    }
}

fn corrupt_byte(stream: &[u8], at: usize) -> Vec<u8> {
    let mut corrupt = stream.to_vec();
    corrupt[at] ^= 0x10;
    corrupt
}

#[test]
fn a_corrupt_stream_is_refused_naming_the_packet() {
    let host = host_frames(3);
    let stream = encode_frames(&host, 1, PacketRates::EVERY_FRAME).unwrap();
    let navigation = PACKETS[0].packet_bytes();
    let calibration = PACKETS[1].packet_bytes();
    let frame_bytes: usize = PACKETS.iter().map(|p| p.packet_bytes()).sum();
    // A data byte of the second packet changed.
    assert!(matches!(
        decode_stream(&corrupt_byte(&stream, navigation + 40)),
        Err(PacketStreamError::Crc { offset, kind: "calibration", .. }) if offset == navigation
    ));
    // The second frame's navigation packet lost.
    let mut lost = stream[..frame_bytes].to_vec();
    lost.extend_from_slice(&stream[frame_bytes + navigation..]);
    assert_eq!(
        decode_stream(&lost),
        Err(PacketStreamError::SequenceGap {
            offset: 2 * frame_bytes - navigation,
            kind: "navigation",
            expected: 1,
            found: 2
        })
    );
    // An APID no kind has (the APID's low byte changed).
    assert_eq!(
        decode_stream(&corrupt_byte(&stream, 1)),
        Err(PacketStreamError::UnknownApid {
            offset: 0,
            apid: 0x111
        })
    );
    // A length field changed, a telecommand, a stream cut inside a packet.
    assert!(matches!(
        decode_stream(&corrupt_byte(&stream, navigation + 5)),
        Err(PacketStreamError::Length { offset, kind: "calibration", found, expected })
            if offset == navigation && found == calibration + 16 && expected == calibration
    ));
    assert!(matches!(
        decode_stream(&corrupt_byte(&stream, 0)),
        Err(PacketStreamError::Header { offset: 0, .. })
    ));
    assert_eq!(
        decode_stream(&stream[..stream.len() - 3]),
        Err(PacketStreamError::Truncated {
            offset: stream.len() - PACKETS[4].packet_bytes(),
            missing: 3
        })
    );
    // Frames out of order (each kind's sequence unbroken).
    let swapped = [&host[FRAME_WORDS..2 * FRAME_WORDS], &host[..FRAME_WORDS]].concat();
    let swapped = encode_frames(&swapped, 1, PacketRates::EVERY_FRAME).unwrap();
    assert!(matches!(
        decode_stream(&swapped),
        Err(PacketStreamError::Frame { offset, frame, .. })
            if offset == frame_bytes && frame == host[0]
    ));
}

/// The UART replay's check of the target's packets (`compare_packets`) finds a changed word,
/// a kind sent when not due and a frame missing.
#[test]
fn the_uart_replay_check_finds_packets_that_differ_from_the_host() {
    use nav_sim::harness::uart_replay::compare_packets;
    let host = host_frames(100);
    let mut rates = PacketRates::EVERY_FRAME;
    rates.set(PacketKind::Health, 25).unwrap();
    let stream = encode_frames(&host, 1, rates).unwrap();
    assert_eq!(
        compare_packets(&stream, rates, &host).unwrap(),
        (100 + 4 + 300, None)
    );
    let every_frame = encode_frames(&host, 1, PacketRates::EVERY_FRAME).unwrap();
    let (_, sent_when_not_due) = compare_packets(&every_frame, rates, &host).unwrap();
    assert!(sent_when_not_due.unwrap().contains("word imu_non_finite"));
    let mut changed = host.clone();
    let velocity_y = OUTPUT_FIELD_NAMES
        .iter()
        .position(|n| *n == "velocity_y_mps")
        .unwrap();
    changed[7 * FRAME_WORDS + velocity_y] ^= 1;
    let (_, difference) = compare_packets(&stream, rates, &changed).unwrap();
    assert!(difference.unwrap().contains("word velocity_y_mps"));
    let (_, missing) = compare_packets(&stream, rates, &[host.clone(), host].concat()).unwrap();
    assert!(missing.unwrap().starts_with("no packets of frame"));
}

#[test]
fn packet_rates_on_the_command_line_name_the_kinds_and_the_range() {
    use nav_sim::logs::telemetry_packets::parse_rate;
    assert_eq!(parse_rate("health=50"), Ok((PacketKind::Health, 50)));
    assert_eq!(
        parse_rate("configuration-warnings=1"),
        Ok((PacketKind::ConfigurationWarnings, 1))
    );
    assert!(parse_rate("health=0")
        .unwrap_err()
        .contains("accepted 1 to 65536"));
    let unknown = parse_rate("status=5").unwrap_err();
    assert!(unknown.contains("no packet kind `status`") && unknown.contains("optional-states"));
    assert!(parse_rate("health").unwrap_err().contains("KIND=FRAMES"));
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(256))]
    /// Any bytes, and a valid stream with any bytes changed, are decoded or refused, never a
    /// panic; a refusal names a packet that starts inside the stream.
    #[test]
    fn the_decoder_never_panics(
        noise in proptest::collection::vec(proptest::prelude::any::<u8>(), 0..600),
        edits in proptest::collection::vec((0_usize..3_312, proptest::prelude::any::<u8>()), 1..4),
    ) {
        let _ = decode_stream(&noise);
        let mut stream = encode_frames(&[7_u64; 3 * FRAME_WORDS], 1, PacketRates::EVERY_FRAME)
            .unwrap();
        for (at, byte) in edits {
            let at = at % stream.len();
            stream[at] = byte;
        }
        if let Err(error) = decode_stream(&stream) {
            let offset = match error {
                PacketStreamError::Truncated { offset, .. }
                | PacketStreamError::Header { offset, .. }
                | PacketStreamError::UnknownApid { offset, .. }
                | PacketStreamError::Length { offset, .. }
                | PacketStreamError::Crc { offset, .. }
                | PacketStreamError::SequenceGap { offset, .. }
                | PacketStreamError::Frame { offset, .. } => offset,
                _ => 0,
            };
            proptest::prop_assert!(offset < stream.len());
        }
    }
}
