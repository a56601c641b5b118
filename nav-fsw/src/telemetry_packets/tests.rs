use super::*;
use crate::replay::OUTPUT_FIELD_NAMES;

/// Output words that tell their index: word `i` is `0x0100_0000_0000_0000 + i` (the frame
/// word `frame`).
fn words(frame: u64) -> [u64; OUTPUT_WORDS] {
    let mut words = [0; OUTPUT_WORDS];
    for (index, word) in words.iter_mut().enumerate() {
        *word = 0x0100_0000_0000_0000 + index as u64;
    }
    words[0] = frame;
    words
}

fn be_u16(bytes: &[u8], at: usize) -> u16 {
    u16::from_be_bytes([bytes[at], bytes[at + 1]])
}

fn be_u64(bytes: &[u8], at: usize) -> u64 {
    u64::from_be_bytes(bytes[at..at + 8].try_into().unwrap())
}

#[test]
fn every_output_word_is_in_exactly_one_place() {
    let mut places = [0_u32; OUTPUT_WORDS];
    for index in SECONDARY_HEADER_WORDS {
        places[index] += 1;
    }
    for packet in &PACKETS {
        for index in packet.words.iter().flat_map(WordSpan::indices) {
            places[index] += 1;
        }
    }
    for (name, count) in OUTPUT_FIELD_NAMES.iter().zip(places) {
        assert_eq!(count, 1, "output word {name} is in {count} places");
    }
    assert_eq!(OUTPUT_FIELD_NAMES[0], "frame");
    assert_eq!(OUTPUT_FIELD_NAMES[1], "time_s");
}

#[test]
fn the_declaration_is_consistent() {
    for (index, (kind, packet)) in PacketKind::ALL.iter().zip(&PACKETS).enumerate() {
        assert_eq!(packet.kind, *kind);
        assert_eq!(kind.index(), index);
        assert_eq!(PacketKind::of_apid(packet.apid), Some(*kind));
        assert!(packet.apid < 0x7FF, "APID 0x7FF is the idle packet's");
    }
    assert_eq!(PacketKind::of_apid(0x100), None);
    assert_eq!(
        MAX_FRAME_PACKET_BYTES,
        PACKETS.iter().map(PacketDeclaration::packet_bytes).sum()
    );
    // Navigation: the primary and secondary headers, 20 words and the CRC.
    assert_eq!(PacketKind::Navigation.declaration().packet_bytes(), 184);
}

#[test]
fn a_packet_has_the_standard_headers_its_words_and_a_crc() {
    let words = words(42);
    let mut encoder = PacketEncoder::new(PacketRates::EVERY_FRAME);
    let mut buffer = [0xEE_u8; 600];
    let length = encoder
        .encode(PacketKind::Calibration, &words, &mut buffer)
        .unwrap();
    assert_eq!(length, 6 + 16 + 30 * 8 + 2);
    assert_eq!(buffer[length], 0xEE, "nothing written past the packet");
    let packet = &buffer[..length];
    // Version 0, type 0, secondary header 1, APID 0x102.
    assert_eq!(be_u16(packet, 0), 0x0800 | 0x102);
    // Unsegmented, count 0; data length = length − 7.
    assert_eq!(be_u16(packet, 2), 0xC000);
    assert_eq!(usize::from(be_u16(packet, 4)), length - 7);
    assert_eq!(be_u64(packet, 6), 42);
    assert_eq!(be_u64(packet, 14), words[1]);
    let gyro_bias_x = OUTPUT_FIELD_NAMES
        .iter()
        .position(|n| *n == "gyro_bias_x")
        .unwrap();
    for slot in 0..30 {
        assert_eq!(be_u64(packet, 22 + 8 * slot), words[gyro_bias_x + slot]);
    }
    // The CRC over the whole packet leaves no residue (CCITT-FALSE has residue 0).
    assert_eq!(PACKET_CRC.checksum(packet), 0);
    assert_eq!(
        be_u16(packet, length - 2),
        PACKET_CRC.checksum(&packet[..length - 2])
    );
}

#[test]
fn sequence_counts_are_per_apid_and_wrap_at_14_bits() {
    let words = words(1);
    let mut encoder = PacketEncoder::new(PacketRates::EVERY_FRAME);
    let mut buffer = [0_u8; MAX_FRAME_PACKET_BYTES];
    for _ in 0..3 {
        encoder
            .encode(PacketKind::Health, &words, &mut buffer)
            .unwrap();
    }
    assert_eq!(be_u16(&buffer, 2) & 0x3FFF, 2);
    assert_eq!(encoder.next_sequence_count(PacketKind::Health), 3);
    assert_eq!(encoder.next_sequence_count(PacketKind::Navigation), 0);
    encoder.sequence_counts[PacketKind::Health.index()] = 0x3FFF;
    encoder
        .encode(PacketKind::Health, &words, &mut buffer)
        .unwrap();
    assert_eq!(be_u16(&buffer, 2), 0xFFFF);
    assert_eq!(encoder.next_sequence_count(PacketKind::Health), 0);
}

#[test]
fn rates_pick_the_frames_and_are_validated() {
    let mut rates = PacketRates::EVERY_FRAME;
    rates.set(PacketKind::Calibration, 10).unwrap();
    rates.set(PacketKind::Health, 25).unwrap();
    assert_eq!(
        rates.set(PacketKind::Health, 0),
        Err(PacketError::Rate {
            kind: PacketKind::Health,
            every_frames: 0
        })
    );
    assert_eq!(rates.every_frames(PacketKind::Health), 25, "unchanged");
    let refused = PacketRates::new([1, 1, 1, MAX_RATE_FRAMES + 1, 1]).unwrap_err();
    assert_eq!(
        refused.to_string(),
        "telemetry rate of `health` packets refused: every 65537 frames, accepted 1 to 65536"
    );
    let mut encoder = PacketEncoder::new(rates);
    let mut buffer = [0_u8; MAX_FRAME_PACKET_BYTES];
    let sizes = PACKETS.map(|packet| packet.packet_bytes());
    let all_but = |skipped: &[usize]| -> usize {
        (0..PACKET_KIND_COUNT)
            .filter(|k| !skipped.contains(k))
            .map(|k| sizes[k])
            .sum()
    };
    assert_eq!(
        encoder.encode_frame(&words(7), &mut buffer),
        Ok(all_but(&[1, 3]))
    );
    assert_eq!(
        encoder.encode_frame(&words(50), &mut buffer),
        Ok(all_but(&[]))
    );
    assert_eq!(
        encoder.encode_frame(&words(20), &mut buffer),
        Ok(all_but(&[3]))
    );
    assert_eq!(encoder.next_sequence_count(PacketKind::Navigation), 3);
    assert_eq!(encoder.next_sequence_count(PacketKind::Calibration), 2);
    assert_eq!(encoder.next_sequence_count(PacketKind::Health), 1);
}

#[test]
fn a_small_buffer_is_refused_and_changes_nothing() {
    let mut encoder = PacketEncoder::new(PacketRates::EVERY_FRAME);
    let mut buffer = [0xAB_u8; MAX_FRAME_PACKET_BYTES - 1];
    let before = encoder.clone();
    assert_eq!(
        encoder.encode_frame(&words(3), &mut buffer),
        Err(PacketError::BufferTooSmall {
            needed: MAX_FRAME_PACKET_BYTES,
            available: MAX_FRAME_PACKET_BYTES - 1
        })
    );
    assert_eq!(
        encoder.encode(PacketKind::Navigation, &words(3), &mut buffer[..183]),
        Err(PacketError::BufferTooSmall {
            needed: 184,
            available: 183
        })
    );
    assert_eq!(encoder, before);
    assert!(buffer.iter().all(|byte| *byte == 0xAB));
}
