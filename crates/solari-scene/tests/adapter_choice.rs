//! `SOLARI_ADAPTER`: choosing one adapter of several, by index or by name, and errors that
//! list the adapters when the request matches none; the viewer's choice among the adapters
//! that can present to its window (CPU only: adapter lists are built here).

use solari_scene::GpuError;
use solari_scene::gpu::{choose_adapter, choose_usable_adapter};
use wgpu::{AdapterInfo, Backend, DeviceType};

fn info(name: &str, device_type: DeviceType) -> AdapterInfo {
    AdapterInfo {
        name: name.into(),
        ..AdapterInfo::new(device_type, Backend::Vulkan)
    }
}

fn machine() -> Vec<AdapterInfo> {
    vec![
        info("llvmpipe (LLVM 19.1.7, 256 bits)", DeviceType::Cpu),
        info("NVIDIA H200", DeviceType::DiscreteGpu),
        info("NVIDIA H200", DeviceType::DiscreteGpu),
        info("Intel(R) UHD Graphics", DeviceType::IntegratedGpu),
    ]
}

#[test]
fn unset_takes_the_first_best_device_type() {
    assert_eq!(choose_adapter(&machine(), None).unwrap(), 1);
    let cpu_and_igpu = vec![machine()[0].clone(), machine()[3].clone()];
    assert_eq!(choose_adapter(&cpu_and_igpu, None).unwrap(), 1);
    assert_eq!(choose_adapter(&machine()[..1], None).unwrap(), 0);
}

#[test]
fn an_index_picks_exactly_that_adapter_even_a_worse_one() {
    for i in 0..4 {
        assert_eq!(choose_adapter(&machine(), Some(&i.to_string())).unwrap(), i);
    }
    assert_eq!(choose_adapter(&machine(), Some(" 2 ")).unwrap(), 2);
}

#[test]
fn a_name_part_matches_case_insensitively_first_match_wins() {
    assert_eq!(choose_adapter(&machine(), Some("h200")).unwrap(), 1);
    assert_eq!(choose_adapter(&machine(), Some("LLVMPIPE")).unwrap(), 0);
    assert_eq!(choose_adapter(&machine(), Some("uhd")).unwrap(), 3);
}

#[test]
fn requests_that_match_nothing_are_errors_listing_the_adapters() {
    for bad in ["4", "99999999999999999999", "radeon", "", "  ", "-1"] {
        match choose_adapter(&machine(), Some(bad)) {
            Err(GpuError::AdapterRequest(msg)) => {
                assert!(msg.contains("SOLARI_ADAPTER"), "{bad:?}: {msg}");
                assert!(msg.contains("1: NVIDIA H200"), "{bad:?}: {msg}");
            }
            other => panic!("{bad:?}: expected an adapter request error, got {other:?}"),
        }
    }
}

#[test]
fn no_adapters_is_no_adapter_whatever_was_asked() {
    for request in [None, Some("0"), Some("nvidia")] {
        assert!(matches!(
            choose_adapter(&[], request),
            Err(GpuError::NoAdapter(_))
        ));
    }
}

#[test]
fn only_usable_adapters_are_chosen_and_a_request_for_another_is_refused() {
    // The H200s cannot present (headless); the integrated GPU is the best that can.
    let usable = [true, false, false, true];
    assert_eq!(choose_usable_adapter(&machine(), &usable, None).unwrap(), 3);
    assert_eq!(
        choose_usable_adapter(&machine(), &[true; 4], None).unwrap(),
        1
    );
    assert_eq!(
        choose_usable_adapter(&machine(), &usable, Some("llvmpipe")).unwrap(),
        0
    );
    match choose_usable_adapter(&machine(), &usable, Some("h200")) {
        Err(GpuError::AdapterRequest(msg)) => {
            assert!(msg.contains("adapter 1, NVIDIA H200"), "{msg}");
            assert!(msg.contains("cannot present"), "{msg}");
        }
        other => panic!("expected a refusal, got {other:?}"),
    }
    match choose_usable_adapter(&machine(), &[false; 4], None) {
        Err(GpuError::NoAdapter(msg)) => assert!(msg.contains("none of the 4"), "{msg}"),
        other => panic!("expected no adapter, got {other:?}"),
    }
    assert!(matches!(
        choose_usable_adapter(&[], &[], None),
        Err(GpuError::NoAdapter(_))
    ));
}
