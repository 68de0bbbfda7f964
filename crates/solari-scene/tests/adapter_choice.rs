//! `SOLARI_ADAPTER`: choosing one adapter of several, by index or by name, and errors that
//! list the adapters when the request matches none (CPU only: adapter lists are built here).

use solari_scene::GpuError;
use solari_scene::gpu::choose_adapter;
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
