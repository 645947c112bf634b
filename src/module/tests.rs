use super::*;

#[test]
fn behavior_strings_round_trip_and_are_sorted() {
    for (rank, behavior) in Behavior::ALL.into_iter().enumerate() {
        assert_eq!(behavior.as_str().parse::<Behavior>(), Ok(behavior));
        assert_eq!(behavior.rank(), Some(rank));
    }
    let names: Vec<_> = Behavior::ALL.iter().map(Behavior::as_str).collect();
    let mut sorted = names.clone();
    sorted.sort_unstable();
    assert_eq!(names, sorted);
    assert_eq!(Behavior::named(""), Err(NameProblem::Empty));
}

#[test]
fn sequences_round_trip() {
    for (rank, sequence) in Sequence::ALL.into_iter().enumerate() {
        assert_eq!(sequence.as_str().parse::<Sequence>(), Ok(sequence));
        assert_eq!(sequence.rank(), Some(rank));
    }
    assert_eq!("".parse::<Sequence>(), Ok(Sequence::Empty));
    let names: Vec<_> = Sequence::ALL.iter().map(Sequence::as_str).collect();
    let mut sorted = names.clone();
    sorted.sort_unstable();
    assert_eq!(names, sorted);
}

/// `[COOP-POL-GET.2]`: behaviours, sequences and so modules are ordered by their strings,
/// built-in and extension names alike.
#[test]
fn names_are_ordered_by_their_strings_built_in_or_not() {
    let behaviors = [
        "adaptive-cruise",
        "approach-assist",
        "avoidance",
        "lane-change",
        "lane-change-assist",
        "merge",
        "zz",
        // Extension names across the words they are kept in: a prefix, `-` and digits before
        // letters, a name of one word and one more byte, the longest names.
        "a",
        "a-",
        "a0",
        "abcdefgh",
        "abcdefgha",
        "abcdefghabcdefghabcdefgg",
        "abcdefghabcdefghabcdefgh",
    ];
    for a in behaviors {
        for b in behaviors {
            let (x, y): (Behavior, Behavior) = (a.parse().unwrap(), b.parse().unwrap());
            assert_eq!(x.cmp(&y), a.cmp(b), "{a} against {b}");
        }
    }
    let sequences = [
        "",
        "approach",
        "back",
        "change",
        "change-again",
        "return",
        "zz",
        "b",
        "back-to-the-lane-at-last",
        "back0",
    ];
    for a in sequences {
        for b in sequences {
            let (x, y): (Sequence, Sequence) = (a.parse().unwrap(), b.parse().unwrap());
            assert_eq!(x.cmp(&y), a.cmp(b), "{a:?} against {b:?}");
        }
    }
    // An extension value holding a built-in name of the other kind is another value: it
    // sorts after the built-in one, never equal to it.
    let Sequence::Extension(avoidance) = Sequence::named("avoidance").unwrap() else {
        panic!("a behaviour's name is a sequence extension");
    };
    assert!(Behavior::Avoidance < Behavior::Extension(avoidance));
    assert!(Behavior::Extension(avoidance) < Behavior::Crosswalk);
    let Behavior::Extension(change) = Behavior::named("change").unwrap() else {
        panic!("a sequence's name is a behaviour extension");
    };
    assert!(Sequence::Change < Sequence::Extension(change));
    assert!(Sequence::Extension(change) < Sequence::Return);
    let module = |b: &str, s: &str| Module::with_sequence(b.parse().unwrap(), s.parse().unwrap());
    assert!(module("aaa", "") < module("lane-change", ""));
    assert!(module("avoidance", "back") < module("avoidance", "change"));
    assert!(module("avoidance", "return") < module("avoidance-x", ""));
}

#[test]
fn an_extension_is_any_other_valid_name() {
    let behavior: Behavior = "emergency-operation".parse().unwrap();
    assert_eq!(behavior.as_str(), "emergency-operation");
    assert_eq!(behavior.rank(), None);
    assert!(matches!(behavior, Behavior::Extension(_)));
    let sequence: Sequence = "back".parse().unwrap();
    assert_eq!(sequence.as_str(), "back");
    assert_eq!(sequence.rank(), None);
    // A name of the other kind is an extension of this one.
    assert!(matches!("change".parse(), Ok(Behavior::Extension(_))));
    assert!(matches!("crosswalk".parse(), Ok(Sequence::Extension(_))));
    // The longest name, and one too long.
    let longest = "a".repeat(Extension::MAX_LEN);
    assert_eq!(Behavior::named(&longest).unwrap().as_str(), longest);
    assert_eq!(
        Behavior::named(&format!("{longest}b")),
        Err(NameProblem::TooLong { len: 25 })
    );
    assert_eq!(Sequence::named("x0-").unwrap().as_str(), "x0-");
}

#[test]
fn a_name_out_of_the_character_set_is_refused_naming_the_byte() {
    for (name, at) in [
        ("lane_change", 4),
        ("LaneChange", 0),
        ("lane-Change", 5),
        ("0-lane", 0),
        ("-lane", 0),
        ("lane change", 4),
        ("avoidance/change", 9),
        ("a.b", 1),
        ("zone\0", 4),
        ("café", 3),
    ] {
        assert_eq!(
            Behavior::named(name),
            Err(NameProblem::Character { at }),
            "{name:?}"
        );
        assert_eq!(
            Sequence::named(name),
            Err(NameProblem::Character { at }),
            "{name:?}"
        );
    }
}

#[test]
fn an_invalid_name_explains_itself() {
    let error = "lane_change".parse::<Behavior>().unwrap_err();
    assert_eq!(
        error,
        InvalidName {
            field: "behavior",
            given: "lane_change".into(),
            problem: NameProblem::Character { at: 4 },
        }
    );
    assert_eq!(
        error.to_string(),
        "\"lane_change\" is not a behavior: byte 4 is not a lower-case ASCII letter, digit or '-'"
    );
    assert_eq!(
        "".parse::<Behavior>().unwrap_err().to_string(),
        "\"\" is not a behavior: it is empty"
    );
    assert_eq!(
        "Back".parse::<Sequence>().unwrap_err().to_string(),
        "\"Back\" is not a sequence: it does not start with a lower-case ASCII letter"
    );
    let long = "x".repeat(40);
    assert_eq!(
        long.parse::<Sequence>().unwrap_err().to_string(),
        format!("{long:?} is not a sequence: it has 40 bytes, over 24")
    );
}

#[test]
fn extensions_sort_among_built_ins_by_name() {
    let [a, ab, b, zz] = ["a", "ab", "b", "zz"].map(|name| name.parse::<Behavior>().unwrap());
    assert!(a < ab && ab < Behavior::AdaptiveCruise && Behavior::Avoidance < b);
    assert!(b < Behavior::Crosswalk && Behavior::VirtualTrafficLight < zz);
    let back: Sequence = "back".parse().unwrap();
    assert!(Sequence::Empty < back && back < Sequence::Change);
    assert_eq!(format!("{back:?}"), "Extension(Extension(\"back\"))");
}

#[test]
fn module_index_is_dense_and_in_module_order() {
    let modules: Vec<Module> = (0..Module::COUNT).filter_map(Module::at_index).collect();
    assert_eq!(modules.len(), Module::COUNT);
    assert_eq!(Module::at_index(Module::COUNT), None);
    for (index, module) in modules.iter().enumerate() {
        assert_eq!(module.index(), Some(index));
    }
    assert!(modules.windows(2).all(|pair| pair[0] < pair[1]));
    let custom = Module::with_sequence(Behavior::Avoidance, "back".parse().unwrap());
    assert_eq!(custom.index(), None);
}

#[test]
fn module_display() {
    assert_eq!(Module::new(Behavior::LaneChange).to_string(), "lane-change");
    assert_eq!(
        Module::with_sequence(Behavior::Avoidance, Sequence::Return).to_string(),
        "avoidance/return"
    );
    let custom = Module::with_sequence("valet".parse().unwrap(), "approach".parse().unwrap());
    assert_eq!(custom.to_string(), "valet/approach");
}

#[test]
fn a_module_with_its_inline_names_is_fifty_bytes() {
    assert_eq!(core::mem::size_of::<Extension>(), Extension::MAX_LEN);
    assert_eq!(core::mem::size_of::<Behavior>(), 25);
    assert_eq!(core::mem::size_of::<Module>(), 50);
}
