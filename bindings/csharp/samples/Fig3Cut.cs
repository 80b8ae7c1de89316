// Kamarianakis & Papagiannakis, Fig. 3, from C#: CesiumMan posed at t = 0.5 s, cut in place by
// the plane y = 0.9 (his chest), the engine's index buffer brought up to date from the change
// alone, and the cut model re-posed with a rotation, a translation and a dilation of the elbow
// and a rotation of the wrist (Fig. 3D); written as a rigged glTF, read back, and re-posed into
// an OBJ.
// Then what an engine cares about, measured: the cost of a call through P/Invoke, of the cut,
// and the managed memory of 10 000 frames (pose, skin into the engine's arrays, tissue step).
//
//   mcs -out:Fig3Cut.exe Cgamesh.cs samples/Fig3Cut.cs
//   LD_LIBRARY_PATH=<dir of libcgamesh_c.so> mono Fig3Cut.exe CesiumMan.glb OUT_DIR [FRAMES]
using System;
using System.Diagnostics;
using System.IO;
using Cgamesh;

public static class Fig3Cut
{
    static int failures = 0;

    static void Expect(bool ok, string what)
    {
        if (ok) return;
        Console.Error.WriteLine("FAILED: " + what);
        ++failures;
    }

    // Fig. 3D: the elbow rotated about (0,1,1) by 0.7 rad, translated and dilated by 0.5; the
    // wrist rotated by 0.3 rad; at t = 0.5 s of the walk.
    static Pose Reposed(Model model)
    {
        var pose = new Pose(model);
        int elbow = model.JointIndex("nodes[14]"), wrist = model.JointIndex("nodes[15]");
        pose.Sample(0, 0.5);
        pose.Rotate(elbow, 0, 1, 1, 40.1);
        pose.Translate(elbow, 0.1, 0, 0);
        pose.Scale(elbow, 0.5);
        pose.Rotate(wrist, 0, 1, 1, 17.2);
        return pose;
    }

    static double Median(double[] x)
    {
        Array.Sort(x);
        return x[x.Length / 2];
    }

    public static int Main(string[] args)
    {
        if (args.Length < 2)
        {
            Console.Error.WriteLine("usage: Fig3Cut.exe MODEL OUT_DIR [FRAMES]");
            return 2;
        }
        string modelPath = args[0], outDir = args[1];
        int frames = args.Length > 2 ? int.Parse(args[2]) : 10000;
        Directory.CreateDirectory(outDir);
        Library.CheckAbi();
        Console.WriteLine("cgamesh " + Library.Version);

        using (Model model = Model.Load(modelPath))
        using (Pose pose = new Pose(model))
        {
            pose.Sample(0, 0.5);

            // The cut, in place; the engine's faces updated from the change.
            int[] facesBefore;
            using (LiveModel live = new LiveModel(model, pose))
            {
                facesBefore = live.Faces(0);
                using (Change change = live.Cut(0, 1, 0, 0.9))
                {
                    File.WriteAllText(Path.Combine(outDir, "cut.json"), change.Json());
                    Expect(change.MeshCount == 1, "one mesh changed");
                    int[] updated = change.UpdateFaces(0, facesBefore);
                    int[] now = live.Faces(0);
                    bool same = updated.Length == now.Length;
                    for (int i = 0; same && i < now.Length; ++i) same = updated[i] == now[i];
                    Expect(same, "the faces updated from the change equal the live mesh's");
                    MeshChange c = change.Mesh(0);
                    Console.WriteLine("cut: " + c.NewVertices + " new vertices, " + c.NewFaces + " new faces, " +
                                      c.MovedFaces + " moved, " + c.RemovedFaces + " removed");
                }

                // Fig. 3D: the cut model re-posed (elbow: rotation about (0,1,1) by 0.7 rad,
                // translation, dilation 0.5; wrist: rotation by 0.3 rad).
                // The written file re-animates as the model in memory does (to float rounding).
                using (Model cut = live.Snapshot())
                {
                    string file = Path.Combine(outDir, "cesium_cut.glb");
                    cut.Save(file);
                    using (Model saved = Model.Load(file))
                    using (Pose inMemory = Reposed(cut))
                    using (Pose fromFile = Reposed(saved))
                    {
                        int v = cut.VertexCount(0);
                        var a = new float[3 * v];
                        var b = new float[3 * v];
                        cut.Skin(inMemory, 0, a);
                        saved.Skin(fromFile, 0, b);
                        double worst = 0;
                        for (int i = 0; i < a.Length; ++i) worst = Math.Max(worst, Math.Abs(a[i] - b[i]));
                        Expect(saved.VertexCount(0) == v && worst < 1e-5, "the saved cut re-poses as in memory (" + worst + ")");
                        saved.Save(Path.Combine(outDir, "cesium_cut_reposed.obj"), fromFile);
                    }
                }
            }

            // Errors arrive as exceptions of the library's hierarchy.
            try
            {
                Model.Load(Path.Combine(outDir, "missing.glb"));
                Expect(false, "a missing file throws");
            }
            catch (FileException e)
            {
                Expect(e is InvalidInputException && e.Message.Contains("missing.glb"), "FileException names the file");
            }
            try
            {
                using (LiveModel live = new LiveModel(model, pose)) live.Cut(0, 1, 0, 100);
                Expect(false, "a plane that misses throws");
            }
            catch (TopologyException)
            {
            }
            try
            {
                model.Skin(pose, 0, new float[5]);
                Expect(false, "a wrong buffer size throws");
            }
            catch (InvalidInputException)
            {
            }

            // The cost of a call through P/Invoke (a call that only reads three counts).
            ModelCounts counts;
            const int calls = 200000;
            for (int i = 0; i < 1000; ++i) Native.cgamesh_model_counts_get(model.Handle, out counts);
            Stopwatch watch = Stopwatch.StartNew();
            for (int i = 0; i < calls; ++i) Native.cgamesh_model_counts_get(model.Handle, out counts);
            watch.Stop();
            double callNs = watch.Elapsed.TotalMilliseconds * 1e6 / calls;

            // The in-place cut, from C# (the live model made untimed, as an engine keeps one).
            var cutMs = new double[31];
            for (int i = 0; i < cutMs.Length; ++i)
                using (LiveModel live = new LiveModel(model, pose))
                {
                    watch.Restart();
                    using (live.Cut(0, 1, 0, 0.9)) { }
                    watch.Stop();
                    cutMs[i] = watch.Elapsed.TotalMilliseconds;
                }

            // 10 000 frames as an engine runs them: sample the clip, step the tissue around a
            // tear, skin into the engine's arrays. No managed allocation may happen.
            using (LiveModel live = new LiveModel(model, pose))
            {
                live.SetTissue(TissueOptions.Default);
                live.Tear(new double[] { 0.5, 1.2, -0.06, 0, 1.2, -0.06, 0.5, 1.25, 0.06, 0, 1.25, 0.06 }).Dispose();
                int v = live.VertexCount(0);
                var positions = new float[3 * v];
                var normals = new float[3 * v];
                double duration = model.ClipDuration(0);
                for (int f = 0; f < 10; ++f)
                {
                    pose.Sample(0, f / 90.0 % duration);
                    live.StepTissue(pose, 1 / 90.0);
                    live.Skin(pose, 0, positions, normals);
                }
                long before = GC.GetTotalMemory(false);
                int collections = GC.CollectionCount(0);
                watch.Restart();
                for (int f = 0; f < frames; ++f)
                {
                    pose.Sample(0, f / 90.0 % duration);
                    live.StepTissue(pose, 1 / 90.0);
                    live.Skin(pose, 0, positions, normals);
                }
                watch.Stop();
                long grown = GC.GetTotalMemory(false) - before;
                int collected = GC.CollectionCount(0) - collections;
                Expect(grown <= 0 && collected == 0, "no managed allocation in " + frames + " frames (" + grown +
                                                         " bytes, " + collected + " collections)");
                bool finite = true;
                foreach (float x in positions) finite &= !float.IsNaN(x) && !float.IsInfinity(x);
                Expect(finite, "the skinned tissue is finite");
                string report = "{\n  \"call_ns\": " + callNs.ToString("F1") +
                                ",\n  \"cut_ms_median\": " + Median(cutMs).ToString("F4") +
                                ",\n  \"frames\": " + frames +
                                ",\n  \"frame_ms\": " + (watch.Elapsed.TotalMilliseconds / frames).ToString("F4") +
                                ",\n  \"managed_bytes_grown\": " + grown +
                                ",\n  \"gc_collections\": " + collected + "\n}\n";
                File.WriteAllText(Path.Combine(outDir, "measurements.json"), report);
                Console.Write(report);
            }
        }
        if (failures > 0) Console.Error.WriteLine(failures + " checks failed");
        return failures > 0 ? 1 : 0;
    }
}
