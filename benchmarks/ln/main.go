// Benchmark driver for rasterkit's svg family: ln's hidden-line method on an OBJ model.
package main

import (
	"fmt"
	"os"
	"strconv"
	"time"

	"github.com/fogleman/ln/ln"
)

func f(s string) float64 { v, _ := strconv.ParseFloat(s, 64); return v }

func main() {
	// lnbench MODEL.obj WIDTH HEIGHT EX EY EZ CX CY CZ FOVY NEAR FAR STEP OUT.svg
	a := os.Args[1:]
	t0 := time.Now()
	mesh, err := ln.LoadOBJ(a[0])
	if err != nil {
		panic(err)
	}
	t1 := time.Now()
	scene := ln.Scene{}
	scene.Add(mesh)
	width, height := f(a[1]), f(a[2])
	eye := ln.Vector{f(a[3]), f(a[4]), f(a[5])}
	center := ln.Vector{f(a[6]), f(a[7]), f(a[8])}
	paths := scene.Render(eye, center, ln.Vector{0, 1, 0}, width, height, f(a[9]), f(a[10]), f(a[11]), f(a[12]))
	t2 := time.Now()
	paths.WriteToSVG(a[13], width, height)
	t3 := time.Now()
	fmt.Printf("load %.3f render %.3f write %.3f paths %d\n", t1.Sub(t0).Seconds(), t2.Sub(t1).Seconds(), t3.Sub(t2).Seconds(), len(paths))
}
