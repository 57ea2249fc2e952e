//! The CARMEN and UCI readers on hand-written lines, good and malformed.

use lplace::io::carmen::{parse_line, CarmenError, CarmenLine, CarmenMessage, CarmenReader};
use lplace::io::uci::{self, UciClass, UciError, UciFormat, UciLine, UciReader};

#[test]
fn flaser_fields_land_where_the_format_says() {
    // 4 beams, pose (1, 2, 0.5), odom pose (1.1, 2.1, 0.6), ipc_ts 12.5.
    let l = parse_line(
        3,
        "FLASER 4 1.0 1.5 2.0 81.91 1 2 0.5 1.1 2.1 0.6 12.5 pippo 12.6",
    )
    .unwrap();
    let CarmenLine::Message(CarmenMessage::Laser(s)) = l else {
        panic!("{l:?}")
    };
    assert_eq!(s.ranges, vec![1.0, 1.5, 2.0, 81.91]);
    assert_eq!((s.pose.x, s.pose.y, s.pose.theta), (1.0, 2.0, 0.5));
    assert_eq!(
        (s.odom_pose.x, s.odom_pose.y, s.odom_pose.theta),
        (1.1, 2.1, 0.6)
    );
    assert_eq!(s.timestamp, 12.5);
    // Even n = 4: step π/4, beams at −90°, −45°, 0°, 45°.
    assert!((s.bearing_step() - std::f64::consts::FRAC_PI_4).abs() < 1e-15);
    let v = s.view(0.0);
    assert_eq!(v.ranges.len(), 4);
    assert_eq!(v.first_bearing, -std::f64::consts::FRAC_PI_2);
}

#[test]
fn flaser_without_host_fields_is_accepted() {
    assert!(matches!(
        parse_line(1, "FLASER 1 2.0 0 0 0 0 0 0 7"),
        Ok(CarmenLine::Message(CarmenMessage::Laser(_)))
    ));
}

#[test]
fn malformed_lines_report_line_and_reason() {
    // Declares 5 beams, holds 3 + pose: 3 + 7 = 10 fields after the count < 5 + 7.
    match parse_line(11, "FLASER 5 1 1 1 0 0 0 0 0 0 1") {
        Err(CarmenError::BeamCount {
            line: 11,
            declared,
            available: 10,
        }) => assert_eq!(declared, "5"),
        other => panic!("{other:?}"),
    }
    match parse_line(12, "FLASER x 1") {
        Err(CarmenError::BeamCount { line: 12, .. }) => {}
        other => panic!("{other:?}"),
    }
    // Third range is garbage: field index 3 after the keyword (count is 0).
    match parse_line(13, "FLASER 3 1 1 abc 0 0 0 0 0 0 1") {
        Err(CarmenError::BadNumber {
            line: 13,
            field: "range",
            index: 3,
            token,
            ..
        }) => assert_eq!(token, "abc"),
        other => panic!("{other:?}"),
    }
    // NaN parses as f64 but is not a range.
    assert!(matches!(
        parse_line(14, "ODOM nan 0 0 0 0 0 1"),
        Err(CarmenError::BadNumber {
            line: 14,
            field: "x",
            ..
        })
    ));
    match parse_line(15, "ODOM 1 2 3 4 5 6") {
        Err(
            e @ CarmenError::MissingField {
                field: "ipc_timestamp",
                ..
            },
        ) => {
            assert_eq!(e.line(), 15);
            assert!(e.to_string().starts_with("line 15:"), "{e}");
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        parse_line(16, "PARAM lonely"),
        Err(CarmenError::MissingField { field: "value", .. })
    ));
}

#[test]
fn comments_blanks_and_unknown_types() {
    assert_eq!(
        parse_line(1, "# message formats defined").unwrap(),
        CarmenLine::Comment
    );
    assert_eq!(parse_line(2, "   ").unwrap(), CarmenLine::Blank);
    assert_eq!(
        parse_line(3, "ROBOTLASER1 0 -1.57 3.14 ...").unwrap(),
        CarmenLine::Other("ROBOTLASER1")
    );
}

#[test]
fn reader_streams_counts_and_continues_after_errors() {
    let log = "\
# header
PARAM robot_frontlaser_offset -0.04 nohost 0
ODOM 0 0 0 0 0 0 0.1 pippo 0.1
FLASER 2 1 2 0 0 0 0 0 0 0.2 pippo 0.2
NEFF 15
ODOM 0 0 zero 0 0 0 0.3 pippo 0.3

NEFF 14
SONAR 1 2 3
FLASER 2 1 2 0.5 0 0 0.5 0 0 0.4 pippo 0.4
";
    let mut rd = CarmenReader::new(log.as_bytes());
    let items: Vec<_> = rd.by_ref().collect();
    let lines: Vec<usize> = items
        .iter()
        .map(|r| match r {
            Ok((l, _)) => *l,
            Err(e) => e.line(),
        })
        .collect();
    assert_eq!(lines, vec![2, 3, 4, 6, 10]);
    assert!(items[3].is_err());
    let st = rd.stats();
    assert_eq!((st.lines, st.lasers, st.odoms, st.params), (10, 2, 1, 1));
    assert_eq!((st.comments, st.blanks, st.errors), (1, 1, 1));
    assert_eq!(st.skipped.get("NEFF"), Some(&2));
    assert_eq!(st.skipped.get("SONAR"), Some(&1));
    assert_eq!(rd.laser_offset(), -0.04);
}

#[test]
fn reader_reports_invalid_utf8_with_its_line() {
    let bytes: &[u8] = b"ODOM 0 0 0 0 0 0 1\n\xff\xfe\nODOM 0 0 0 0 0 0 2\n";
    let items: Vec<_> = CarmenReader::new(bytes).collect();
    assert_eq!(items.len(), 3);
    assert!(matches!(items[1], Err(CarmenError::NotUtf8 { line: 2 })));
}

/// A 3 MiB line (a corrupt block with no line break) is one bad line, reported and skipped
/// without being held; the messages after it are read with their own line numbers.
#[test]
fn reader_skips_an_overlong_line_with_its_number() {
    let mut bytes = b"ODOM 0 0 0 0 0 0 1\n".to_vec();
    bytes.extend(vec![b'9'; 3 << 20]);
    bytes.extend_from_slice(b"\nODOM 0 0 0 0 0 0 2\n");
    let mut rd = CarmenReader::new(&bytes[..]);
    let items: Vec<_> = rd.by_ref().collect();
    assert_eq!(items.len(), 3);
    assert!(matches!(items[1], Err(CarmenError::TooLong { line: 2 })));
    assert!(matches!(items[2], Ok((3, _))), "{:?}", items[2]);
    assert_eq!((rd.stats().lines, rd.stats().errors), (3, 1));
}

#[test]
fn uci_rows_of_all_three_files() {
    let l24 = "0.438,0.498,3.625,3.645,5.000,2.918,5.000,2.351,2.332,2.643,1.698,1.687,1.698,1.717,1.744,0.593,0.502,0.493,0.504,0.445,0.431,0.444,0.440,0.429,Slight-Right-Turn";
    let UciLine::Row(r) = uci::parse_line(2, l24).unwrap() else {
        panic!()
    };
    assert_eq!(r.format, UciFormat::Sensors24);
    assert_eq!(r.ranges().len(), 24);
    // US19 (left) is the 19th value, US7 (right) the 7th.
    assert_eq!((r.left(), r.right()), (0.504, Some(5.0)));
    assert_eq!(r.sensor(13), Some(1.698));
    assert_eq!(r.sensor(25), None);
    let UciLine::Row(r) = uci::parse_line(1, "1.687,0.445,2.332,0.429,Move-Forward").unwrap()
    else {
        panic!()
    };
    assert_eq!(
        (r.format, r.class, r.right()),
        (UciFormat::Simplified4, UciClass::MoveForward, Some(2.332))
    );
    let UciLine::Row(r) = uci::parse_line(1, "1.687,0.445,Sharp-Right-Turn\r").unwrap() else {
        panic!()
    };
    assert_eq!((r.format, r.right()), (UciFormat::Simplified2, None));
    let header = "S1,S2,S3,S4,S5,S6,S7,S8,S9,S10,S11,S12,S13,S14,S15,S16,S17,S18,S19,S20,S21,S22,S23,S24,OUTPUT";
    assert_eq!(uci::parse_line(1, header).unwrap(), UciLine::Header);
}

#[test]
fn uci_geometry() {
    // US13 forward, US19 left (+90°), US7 right (−90°), US1 backwards (−180°).
    let deg = |k| uci::sensor_bearing(k).unwrap().to_degrees();
    assert!((deg(13) - 0.0).abs() < 1e-12);
    assert!((deg(19) - 90.0).abs() < 1e-12);
    assert!((deg(7) + 90.0).abs() < 1e-12);
    assert!((deg(1) + 180.0).abs() < 1e-12);
    assert_eq!(uci::sensor_bearing(0), None);
}

#[test]
fn uci_malformed_rows() {
    assert!(matches!(
        uci::parse_line(5, "1,2,3,4"),
        Err(UciError::FieldCount { line: 5, found: 4 })
    ));
    match uci::parse_line(6, "1.0,inf,Move-Forward") {
        Err(UciError::BadNumber {
            line: 6,
            column: 2,
            token,
        }) => assert_eq!(token, "inf"),
        other => panic!("{other:?}"),
    }
    match uci::parse_line(7, "1.0,2.0,Reverse") {
        Err(UciError::UnknownClass { line: 7, token }) => assert_eq!(token, "Reverse"),
        other => panic!("{other:?}"),
    }
    let rd = UciReader::new(
        "1.0,2.0,Move-Forward\n1.0,x,Move-Forward\n\n3.0,4.0,Slight-Left-Turn\n".as_bytes(),
    );
    let got: Vec<_> = rd
        .map(|r| r.map(|(l, _)| l).map_err(|e| e.line()))
        .collect();
    assert_eq!(got, vec![Ok(1), Err(2), Ok(4)]);
}
