//! The frame span timer (GPU: lavapipe in CI): one finite, non-negative span per frame, each
//! frame's queue upload seen by that frame's commands and no other (the bench relies on it for
//! per-frame uniforms while frames run back to back), and frame counts it cannot time refused.

use solari_scene::gpu::test_gpu;
use solari_scene::gpu_timer::FrameSpanTimer;

#[test]
fn frames_back_to_back_each_see_their_own_upload() {
    let Some(gpu) = test_gpu() else { return };
    let timer = match FrameSpanTimer::new(&gpu, 8) {
        Ok(t) => t,
        Err(e) if std::env::var("SOLARI_REQUIRE_GPU").as_deref() != Ok("1") => {
            eprintln!("skipped: {e}");
            return;
        }
        Err(e) => panic!("{e}"),
    };
    assert_eq!(timer.capacity(), 8);
    let buffer = |size, usage| {
        gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size,
            usage,
            mapped_at_creation: false,
        })
    };
    use wgpu::BufferUsages as U;
    let upload = buffer(4, U::COPY_DST | U::COPY_SRC);
    let seen = buffer(32, U::COPY_DST | U::COPY_SRC);
    let frames = 7;
    let spans = timer
        .time(
            &gpu,
            frames,
            |i, _| {
                gpu.queue
                    .write_buffer(&upload, 0, bytemuck::bytes_of(&(100 + i)));
                Ok(())
            },
            |i, e| {
                e.copy_buffer_to_buffer(&upload, 0, &seen, u64::from(i) * 4, 4);
                Ok(())
            },
        )
        .expect("timed");
    assert_eq!(spans.len(), frames as usize);
    assert!(
        spans.iter().all(|s| s.is_finite() && *s >= 0.0),
        "{spans:?}"
    );
    let read = gpu.read_buffer(&seen, 32).expect("readback");
    let words: Vec<u32> = bytemuck::pod_collect_to_vec(&read);
    assert_eq!(&words[..7], &[100, 101, 102, 103, 104, 105, 106]);

    for bad in [0, 9] {
        let err = timer
            .time(&gpu, bad, |_, _| Ok(()), |_, _| Ok(()))
            .expect_err("a count the timer was not made for");
        assert!(err.to_string().contains(&format!("{bad} frames")), "{err}");
    }
}
