//! The ground side of the telemetry packets (nav-fsw `telemetry_packets`,
//! docs/reference/telemetry-packets.md): a packet stream decoded into frames of output words,
//! every header, length, CRC and sequence count checked, and the output-record CSV both the
//! decoder and `nav-sim replay --records` write, one row per frame, so the two compare as text.
//!
//! The primary header is read by the `spacepackets` crate (CCSDS 133.0-B-2), independently of
//! the flight encoder.

use std::io::Write;

use nav_fsw::replay::{OUTPUT_FIELD_NAMES, OUTPUT_WORDS};
use nav_fsw::telemetry_packets::{
    word_type, PacketEncoder, PacketKind, PacketRates, WordSpan, WordType, CRC_BYTES,
    MAX_FRAME_PACKET_BYTES, PACKET_CRC, PRIMARY_HEADER_BYTES, SECONDARY_HEADER_WORDS,
    SEQUENCE_COUNT_MODULUS,
};
use spacepackets::{CcsdsPacket, PacketType, SequenceFlags, SpHeader};

/// Why a packet stream is refused; `offset` is the byte where the packet starts.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum PacketStreamError {
    /// The stream ends inside a packet.
    #[error("packet at byte {offset}: the stream ends {missing} bytes before the packet does")]
    Truncated {
        /// Start of the packet.
        offset: usize,
        /// Bytes missing.
        missing: usize,
    },
    /// A primary header that is not an unsegmented version-0 telemetry packet with a
    /// secondary header.
    #[error("packet at byte {offset}: {what} (telemetry packets are version 0, type telemetry, with a secondary header, unsegmented)")]
    Header {
        /// Start of the packet.
        offset: usize,
        /// What is wrong.
        what: String,
    },
    /// An APID no packet kind has.
    #[error("packet at byte {offset}: APID {apid:#05x} is no telemetry packet kind's")]
    UnknownApid {
        /// Start of the packet.
        offset: usize,
        /// The APID.
        apid: u16,
    },
    /// A data length other than the kind's.
    #[error("packet at byte {offset}: `{kind}` packet of {found} bytes, the kind has {expected}")]
    Length {
        /// Start of the packet.
        offset: usize,
        /// The kind's name.
        kind: &'static str,
        /// Bytes the header declares.
        found: usize,
        /// Bytes of the kind.
        expected: usize,
    },
    /// The packet error control does not match: the bytes were changed.
    #[error("packet at byte {offset}: `{kind}` packet's CRC {stored:#06x}, its bytes give {computed:#06x}")]
    Crc {
        /// Start of the packet.
        offset: usize,
        /// The kind's name.
        kind: &'static str,
        /// The CRC in the packet.
        stored: u16,
        /// The CRC of its bytes.
        computed: u16,
    },
    /// A sequence count that does not follow the APID's last one: packets were lost.
    #[error("packet at byte {offset}: `{kind}` sequence count {found}, expected {expected} (packets lost or repeated)")]
    SequenceGap {
        /// Start of the packet.
        offset: usize,
        /// The kind's name.
        kind: &'static str,
        /// The count expected.
        expected: u16,
        /// The count found.
        found: u16,
    },
    /// The frame counter does not increase, a kind comes twice in a frame, or the packets of
    /// one frame disagree on its time.
    #[error("packet at byte {offset}: frame {frame}: {what}")]
    Frame {
        /// Start of the packet.
        offset: usize,
        /// The packet's frame counter.
        frame: u64,
        /// What is wrong.
        what: String,
    },
}

/// One frame's output words as the packets brought them (`None`: the word's kind was not
/// sent in that frame).
pub type DecodedFrame = [Option<u64>; OUTPUT_WORDS];

/// Decodes a packet stream into frames (module docs).
///
/// # Errors
/// [`PacketStreamError`] for the first packet that is truncated, malformed, of an unknown
/// APID or another length, fails its CRC, or breaks its APID's sequence or the frame order.
pub fn decode_stream(bytes: &[u8]) -> Result<Vec<DecodedFrame>, PacketStreamError> {
    let mut frames: Vec<DecodedFrame> = Vec::new();
    let mut next_counts: [Option<u16>; PacketKind::ALL.len()] = [None; PacketKind::ALL.len()];
    let mut kinds_in_frame = [false; PacketKind::ALL.len()];
    let mut offset = 0;
    while offset < bytes.len() {
        let rest = bytes.get(offset..).unwrap_or_default();
        let packet = read_packet(rest, offset)?;
        let count_slot = &mut next_counts[packet.kind.index()];
        if let Some(expected) = *count_slot {
            if expected != packet.sequence_count {
                return Err(PacketStreamError::SequenceGap {
                    offset,
                    kind: packet.kind.declaration().name,
                    expected,
                    found: packet.sequence_count,
                });
            }
        }
        *count_slot = Some((packet.sequence_count + 1) % SEQUENCE_COUNT_MODULUS);
        let frame_error = |what: String| PacketStreamError::Frame {
            offset,
            frame: packet.frame,
            what,
        };
        let current = frames.last().and_then(|frame| frame[0].zip(frame[1]));
        match current {
            Some((frame, time)) if frame == packet.frame => {
                if time != packet.time_bits {
                    return Err(frame_error(format!(
                        "time {} after {} in the same frame",
                        f64::from_bits(packet.time_bits),
                        f64::from_bits(time)
                    )));
                }
                if kinds_in_frame[packet.kind.index()] {
                    return Err(frame_error(format!(
                        "a second `{}` packet",
                        packet.kind.declaration().name
                    )));
                }
            }
            Some((frame, _)) if frame > packet.frame => {
                return Err(frame_error(format!("after frame {frame}")));
            }
            _ => {
                let mut words = [None; OUTPUT_WORDS];
                words[SECONDARY_HEADER_WORDS.start] = Some(packet.frame);
                words[SECONDARY_HEADER_WORDS.start + 1] = Some(packet.time_bits);
                frames.push(words);
                kinds_in_frame = [false; PacketKind::ALL.len()];
            }
        }
        kinds_in_frame[packet.kind.index()] = true;
        if let Some(frame) = frames.last_mut() {
            for (index, word) in packet.words {
                frame[index] = Some(word);
            }
        }
        offset += packet.length;
    }
    Ok(frames)
}

/// One checked packet.
struct Packet {
    kind: PacketKind,
    length: usize,
    sequence_count: u16,
    frame: u64,
    time_bits: u64,
    /// (output word index, word) of its data field.
    words: Vec<(usize, u64)>,
}

fn read_packet(bytes: &[u8], offset: usize) -> Result<Packet, PacketStreamError> {
    let truncated = |length: usize| PacketStreamError::Truncated {
        offset,
        missing: length - bytes.len(),
    };
    let (header, _) =
        SpHeader::from_be_bytes(bytes).map_err(|_| truncated(PRIMARY_HEADER_BYTES))?;
    let header_error = |what: String| PacketStreamError::Header { offset, what };
    if header.ccsds_version().value() != 0 {
        return Err(header_error(format!("version {}", header.ccsds_version())));
    }
    if header.packet_type() != PacketType::Tm {
        return Err(header_error("a telecommand packet".into()));
    }
    if !header.sec_header_flag() {
        return Err(header_error("no secondary header".into()));
    }
    if header.sequence_flags() != SequenceFlags::Unsegmented {
        return Err(header_error(format!(
            "segmented ({:?})",
            header.sequence_flags()
        )));
    }
    let apid = header.apid().value();
    let kind = PacketKind::of_apid(apid).ok_or(PacketStreamError::UnknownApid { offset, apid })?;
    let declaration = kind.declaration();
    let length = header.packet_len();
    if length != declaration.packet_bytes() {
        return Err(PacketStreamError::Length {
            offset,
            kind: declaration.name,
            found: length,
            expected: declaration.packet_bytes(),
        });
    }
    let packet = bytes.get(..length).ok_or_else(|| truncated(length))?;
    let (body, crc) = packet.split_at(length - CRC_BYTES);
    let stored = u16::from_be_bytes([crc[0], crc[1]]);
    let computed = PACKET_CRC.checksum(body);
    if stored != computed {
        return Err(PacketStreamError::Crc {
            offset,
            kind: declaration.name,
            stored,
            computed,
        });
    }
    let mut words = body[PRIMARY_HEADER_BYTES..]
        .chunks_exact(8)
        .map(|chunk| u64::from_be_bytes(chunk.try_into().unwrap_or_default()));
    let frame = words.next().unwrap_or_default();
    let time_bits = words.next().unwrap_or_default();
    let indices = declaration.words.iter().flat_map(WordSpan::indices);
    Ok(Packet {
        kind,
        length,
        sequence_count: header.seq_count().value(),
        frame,
        time_bits,
        words: indices.zip(words).collect(),
    })
}

/// The packets of frames' output records (`frame_words`: per frame [`OUTPUT_WORDS`] words,
/// then `trailing_words` words that are not the record, such as the target's cost word) at
/// `rates`, as the flight encoder writes them.
///
/// # Errors
/// A record the encoder refuses (it never does with its own buffer size).
pub fn encode_frames(
    frame_words: &[u64],
    trailing_words: usize,
    rates: PacketRates,
) -> Result<Vec<u8>, nav_fsw::telemetry_packets::PacketError> {
    let mut encoder = PacketEncoder::new(rates);
    let mut stream = Vec::new();
    let mut buffer = [0_u8; MAX_FRAME_PACKET_BYTES];
    for frame in frame_words.chunks_exact(OUTPUT_WORDS + trailing_words) {
        let mut record = [0_u64; OUTPUT_WORDS];
        record.copy_from_slice(&frame[..OUTPUT_WORDS]);
        let length = encoder.encode_frame(&record, &mut buffer)?;
        stream.extend_from_slice(&buffer[..length]);
    }
    Ok(stream)
}

/// The output-record CSV's header: the output words' names.
pub fn record_csv_header() -> String {
    OUTPUT_FIELD_NAMES.join(",")
}

/// One output-record CSV row: unsigned words as integers, floats in the shortest form that
/// reads back to the same bits (NaN of another payload than Rust's `f64::NAN` as its bits in
/// hexadecimal), an empty cell for a word not received.
pub fn record_csv_row(words: &DecodedFrame) -> String {
    let mut cells = Vec::with_capacity(OUTPUT_WORDS);
    for (index, word) in words.iter().enumerate() {
        cells.push(match (word, word_type(index)) {
            (None, _) => String::new(),
            (Some(word), WordType::Unsigned) => word.to_string(),
            (Some(word), WordType::Float) => float_cell(*word),
        });
    }
    cells.join(",")
}

fn float_cell(bits: u64) -> String {
    let value = f64::from_bits(bits);
    if value.is_finite() {
        ryu::Buffer::new().format_finite(value).to_owned()
    } else if value.is_nan() && bits != f64::NAN.to_bits() {
        format!("{bits:#018x}")
    } else {
        value.to_string()
    }
}

/// Writes frames as the output-record CSV (header, one row per frame).
///
/// # Errors
/// I/O errors of `output`.
pub fn write_record_csv<W: Write>(
    frames: impl IntoIterator<Item = DecodedFrame>,
    output: W,
) -> std::io::Result<u64> {
    let mut output = std::io::BufWriter::new(output);
    writeln!(output, "{}", record_csv_header())?;
    let mut rows = 0;
    for frame in frames {
        writeln!(output, "{}", record_csv_row(&frame))?;
        rows += 1;
    }
    output.flush()?;
    Ok(rows)
}

/// A whole output record as a decoded frame (every word received).
pub fn full_frame(words: &[u64; OUTPUT_WORDS]) -> DecodedFrame {
    words.map(Some)
}

/// A `KIND=N` rate (`navigation=1`, `health=50`): the kind by its declared name, sent every
/// N frames.
///
/// # Errors
/// A message naming the kinds or the accepted rates.
pub fn parse_rate(text: &str) -> Result<(PacketKind, u32), String> {
    let names: Vec<&str> = PacketKind::ALL
        .iter()
        .map(|kind| kind.declaration().name)
        .collect();
    let (name, frames) = text
        .split_once('=')
        .ok_or_else(|| format!("expected KIND=FRAMES, KIND one of {}", names.join(", ")))?;
    let kind = PacketKind::ALL
        .into_iter()
        .find(|kind| kind.declaration().name == name)
        .ok_or_else(|| format!("no packet kind `{name}`: one of {}", names.join(", ")))?;
    let every_frames: u32 = frames
        .parse()
        .map_err(|_| format!("`{frames}` is not a whole number of frames"))?;
    let mut rates = PacketRates::EVERY_FRAME;
    rates
        .set(kind, every_frames)
        .map_err(|error| error.to_string())?;
    Ok((kind, every_frames))
}
