// SPDX-License-Identifier: BSD-3-Clause
#include "Partition/MaxFlow.h"

#include <algorithm>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>

namespace shapediameter
{

MaxFlowGraph::MaxFlowGraph(
  std::size_t nodeCount, const std::vector<std::int64_t>& first, const std::vector<std::int64_t>& second)
{
  constexpr std::size_t limit = static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()) - 1;
  if (first.size() != second.size())
  {
    throw std::invalid_argument("max-flow graph: pair lists of different sizes");
  }
  if (nodeCount > limit || 2 * first.size() > limit)
  {
    throw std::invalid_argument("max-flow graph: too many nodes or arcs for 32-bit indices");
  }
  const auto n = static_cast<std::int64_t>(nodeCount);
  std::vector<std::int32_t> degree(nodeCount, 0);
  for (std::size_t p = 0; p < first.size(); ++p)
  {
    const std::int64_t a = first[p], b = second[p];
    if (a < 0 || b < 0 || a >= n || b >= n || a == b)
    {
      throw std::invalid_argument("max-flow graph: pair " + std::to_string(p) + " has invalid nodes");
    }
    ++degree[static_cast<std::size_t>(a)];
    ++degree[static_cast<std::size_t>(b)];
  }
  this->ArcStart.assign(nodeCount + 1, 0);
  for (std::size_t i = 0; i < nodeCount; ++i)
  {
    this->ArcStart[i + 1] = this->ArcStart[i] + degree[i];
  }
  const std::size_t arcCount = 2 * first.size();
  this->Arcs.resize(arcCount);
  this->PairArc.resize(first.size());
  this->ArcPairIndex.resize(arcCount);
  std::vector<std::int32_t> fill(this->ArcStart.begin(), this->ArcStart.end() - 1);
  for (std::size_t p = 0; p < first.size(); ++p)
  {
    const auto a = static_cast<std::int32_t>(first[p]);
    const auto b = static_cast<std::int32_t>(second[p]);
    const std::int32_t forward = fill[static_cast<std::size_t>(a)]++;
    const std::int32_t backward = fill[static_cast<std::size_t>(b)]++;
    this->Arcs[static_cast<std::size_t>(forward)].head = b;
    this->Arcs[static_cast<std::size_t>(backward)].head = a;
    this->Arcs[static_cast<std::size_t>(forward)].sister = backward;
    this->Arcs[static_cast<std::size_t>(backward)].sister = forward;
    this->PairArc[p] = forward;
    this->ArcPairIndex[static_cast<std::size_t>(forward)] = static_cast<std::int32_t>(p);
    this->ArcPairIndex[static_cast<std::size_t>(backward)] = static_cast<std::int32_t>(p);
  }
  this->TerminalCapacity.assign(nodeCount, 0.0);
  this->Nodes.assign(nodeCount, Node());
}

void MaxFlowGraph::SetTerminalCapacities(std::size_t node, double fromSource, double toSink)
{
  // Only the difference needs a path through the graph; the common part flows s->i->t.
  this->FlowFromTerminals += std::min(fromSource, toSink);
  this->TerminalCapacity[node] = fromSource - toSink;
}

void MaxFlowGraph::SetPairCapacities(std::size_t pair, double forward, double backward)
{
  const auto arc = static_cast<std::size_t>(this->PairArc[pair]);
  this->Arcs[arc].residual = forward;
  this->Arcs[static_cast<std::size_t>(this->Arcs[arc].sister)].residual = backward;
}

void MaxFlowGraph::MakeActive(std::int32_t node)
{
  if (!this->Nodes[static_cast<std::size_t>(node)].active)
  {
    this->Nodes[static_cast<std::size_t>(node)].active = 1;
    if (this->ActiveHead > 4096 && 2 * this->ActiveHead > this->ActiveQueue.size())
    {
      // Drop the consumed front so the queue stays O(nodes) however often nodes reactivate.
      this->ActiveQueue.erase(this->ActiveQueue.begin(), this->ActiveQueue.begin() + static_cast<std::ptrdiff_t>(this->ActiveHead));
      this->ActiveHead = 0;
    }
    this->ActiveQueue.push_back(node);
  }
}

std::int32_t MaxFlowGraph::NextActive()
{
  while (this->ActiveHead < this->ActiveQueue.size())
  {
    const std::int32_t node = this->ActiveQueue[this->ActiveHead++];
    this->Nodes[static_cast<std::size_t>(node)].active = 0;
    if (this->Nodes[static_cast<std::size_t>(node)].parent != NoParent)
    {
      return node;
    }
  }
  this->ActiveQueue.clear();
  this->ActiveHead = 0;
  return -1;
}

bool MaxFlowGraph::Grow(std::int32_t node, std::int32_t& meetingArc)
{
  const auto i = static_cast<std::size_t>(node);
  const bool sinkTree = this->Nodes[i].inSinkTree != 0;
  for (std::int32_t a = this->ArcStart[i]; a < this->ArcStart[i + 1]; ++a)
  {
    const std::int32_t sister = this->Arcs[static_cast<std::size_t>(a)].sister;
    // The arc the flow would take: i->j when growing the source tree, j->i for the sink tree.
    const std::int32_t along = sinkTree ? sister : a;
    if (!(this->Arcs[static_cast<std::size_t>(along)].residual > 0.0))
    {
      continue;
    }
    const auto j = static_cast<std::size_t>(this->Arcs[static_cast<std::size_t>(a)].head);
    if (this->Nodes[j].parent == NoParent)
    {
      this->Nodes[j].inSinkTree = sinkTree ? 1 : 0;
      this->Nodes[j].parent = sister;
      this->Nodes[j].timestamp = this->Nodes[i].timestamp;
      this->Nodes[j].distance = this->Nodes[i].distance + 1;
      this->MakeActive(static_cast<std::int32_t>(j));
    }
    else if ((this->Nodes[j].inSinkTree != 0) != sinkTree)
    {
      meetingArc = along; // from the source tree to the sink tree
      return true;
    }
    else if (this->Nodes[j].timestamp <= this->Nodes[i].timestamp && this->Nodes[j].distance > this->Nodes[i].distance)
    {
      // A shorter way to the terminal for j: paths stay short, augmentations cheap.
      this->Nodes[j].parent = sister;
      this->Nodes[j].timestamp = this->Nodes[i].timestamp;
      this->Nodes[j].distance = this->Nodes[i].distance + 1;
    }
  }
  return false;
}

void MaxFlowGraph::Augment(std::int32_t meetingArc)
{
  const auto meeting = static_cast<std::size_t>(meetingArc);
  const std::int32_t sourceEnd = this->Arcs[static_cast<std::size_t>(this->Arcs[meeting].sister)].head;
  const std::int32_t sinkEnd = this->Arcs[meeting].head;

  // Bottleneck: source side (flow parent -> child), then sink side (child -> parent).
  double bottleneck = this->Arcs[meeting].residual;
  std::size_t x = static_cast<std::size_t>(sourceEnd);
  for (std::int32_t p = this->Nodes[x].parent; p != TerminalParent; p = this->Nodes[x].parent)
  {
    bottleneck = std::min(bottleneck, this->Arcs[static_cast<std::size_t>(this->Arcs[static_cast<std::size_t>(p)].sister)].residual);
    x = static_cast<std::size_t>(this->Arcs[static_cast<std::size_t>(p)].head);
  }
  bottleneck = std::min(bottleneck, this->TerminalCapacity[x]);
  x = static_cast<std::size_t>(sinkEnd);
  for (std::int32_t p = this->Nodes[x].parent; p != TerminalParent; p = this->Nodes[x].parent)
  {
    bottleneck = std::min(bottleneck, this->Arcs[static_cast<std::size_t>(p)].residual);
    x = static_cast<std::size_t>(this->Arcs[static_cast<std::size_t>(p)].head);
  }
  bottleneck = std::min(bottleneck, -this->TerminalCapacity[x]);

  // Push it; every arc that saturates cuts its child off: an orphan.
  this->Arcs[static_cast<std::size_t>(this->Arcs[meeting].sister)].residual += bottleneck;
  this->Arcs[meeting].residual -= bottleneck;
  x = static_cast<std::size_t>(sourceEnd);
  for (std::int32_t p = this->Nodes[x].parent; p != TerminalParent; p = this->Nodes[x].parent)
  {
    const auto up = static_cast<std::size_t>(p);
    const auto down = static_cast<std::size_t>(this->Arcs[up].sister);
    this->Arcs[up].residual += bottleneck;
    this->Arcs[down].residual -= bottleneck;
    const std::size_t next = static_cast<std::size_t>(this->Arcs[up].head);
    if (this->Arcs[down].residual == 0.0)
    {
      this->CutOff(x);
    }
    x = next;
  }
  this->TerminalCapacity[x] -= bottleneck;
  if (this->TerminalCapacity[x] == 0.0)
  {
    this->CutOff(x);
  }
  x = static_cast<std::size_t>(sinkEnd);
  for (std::int32_t p = this->Nodes[x].parent; p != TerminalParent; p = this->Nodes[x].parent)
  {
    const auto up = static_cast<std::size_t>(p);
    this->Arcs[static_cast<std::size_t>(this->Arcs[up].sister)].residual += bottleneck;
    this->Arcs[up].residual -= bottleneck;
    const std::size_t next = static_cast<std::size_t>(this->Arcs[up].head);
    if (this->Arcs[up].residual == 0.0)
    {
      this->CutOff(x);
    }
    x = next;
  }
  this->TerminalCapacity[x] += bottleneck;
  if (this->TerminalCapacity[x] == 0.0)
  {
    this->CutOff(x);
  }
  this->FlowValue += bottleneck;
}

void MaxFlowGraph::CutOff(std::size_t node)
{
  this->Nodes[node].parent = OrphanParent;
  this->NewOrphans.push_back(static_cast<std::int32_t>(node));
}

std::int64_t MaxFlowGraph::OriginDistance(std::int32_t node)
{
  std::int64_t distance = 0;
  auto k = static_cast<std::size_t>(node);
  while (true)
  {
    if (this->Nodes[k].timestamp == this->Time)
    {
      distance += this->Nodes[k].distance;
      break;
    }
    const std::int32_t p = this->Nodes[k].parent;
    ++distance;
    if (p == TerminalParent)
    {
      this->Nodes[k].timestamp = this->Time;
      this->Nodes[k].distance = 1;
      break;
    }
    if (p == OrphanParent)
    {
      return -1;
    }
    k = static_cast<std::size_t>(this->Arcs[static_cast<std::size_t>(p)].head);
  }
  // Remember the distances along the chain: later orphans stop here.
  std::int64_t marked = distance;
  for (k = static_cast<std::size_t>(node); this->Nodes[k].timestamp != this->Time;
       k = static_cast<std::size_t>(this->Arcs[static_cast<std::size_t>(this->Nodes[k].parent)].head))
  {
    this->Nodes[k].timestamp = this->Time;
    this->Nodes[k].distance = static_cast<std::int32_t>(marked--);
  }
  return distance;
}

void MaxFlowGraph::Adopt(std::int32_t node)
{
  const auto i = static_cast<std::size_t>(node);
  const bool sinkTree = this->Nodes[i].inSinkTree != 0;
  std::int32_t bestArc = NoParent;
  std::int64_t bestDistance = std::numeric_limits<std::int64_t>::max();
  for (std::int32_t a = this->ArcStart[i]; a < this->ArcStart[i + 1]; ++a)
  {
    // A parent j must be able to send (source tree: j->i) or receive (sink tree: i->j).
    const std::int32_t along = sinkTree ? a : this->Arcs[static_cast<std::size_t>(a)].sister;
    if (!(this->Arcs[static_cast<std::size_t>(along)].residual > 0.0))
    {
      continue;
    }
    const std::int32_t j = this->Arcs[static_cast<std::size_t>(a)].head;
    const auto jj = static_cast<std::size_t>(j);
    if ((this->Nodes[jj].inSinkTree != 0) != sinkTree || this->Nodes[jj].parent == NoParent)
    {
      continue;
    }
    const std::int64_t distance = this->OriginDistance(j);
    if (distance >= 0 && distance < bestDistance)
    {
      bestArc = a;
      bestDistance = distance;
    }
  }
  if (bestArc != NoParent)
  {
    this->Nodes[i].parent = bestArc;
    this->Nodes[i].timestamp = this->Time;
    this->Nodes[i].distance = static_cast<std::int32_t>(bestDistance + 1);
    return;
  }
  // No way back to its terminal: the node leaves the tree, its children become orphans and
  // the neighbours that could grow into it again become active.
  this->Nodes[i].parent = NoParent;
  for (std::int32_t a = this->ArcStart[i]; a < this->ArcStart[i + 1]; ++a)
  {
    const auto j = static_cast<std::size_t>(this->Arcs[static_cast<std::size_t>(a)].head);
    const std::int32_t p = this->Nodes[j].parent;
    if ((this->Nodes[j].inSinkTree != 0) != sinkTree || p == NoParent)
    {
      continue;
    }
    const std::int32_t along = sinkTree ? a : this->Arcs[static_cast<std::size_t>(a)].sister;
    if (this->Arcs[static_cast<std::size_t>(along)].residual > 0.0)
    {
      this->MakeActive(static_cast<std::int32_t>(j));
    }
    if (p >= 0 && this->Arcs[static_cast<std::size_t>(p)].head == node)
    {
      this->Nodes[j].parent = OrphanParent;
      this->OrphanQueue.push_back(static_cast<std::int32_t>(j));
    }
  }
}

double MaxFlowGraph::Solve()
{
  const std::size_t n = this->NodeCount();
  this->ActiveQueue.clear();
  this->ActiveHead = 0;
  this->NewOrphans.clear();
  this->OrphanQueue.clear();
  this->OrphanHead = 0;
  this->Time = 0;
  this->FlowValue = this->FlowFromTerminals;
  this->FlowFromTerminals = 0.0;
  for (std::size_t i = 0; i < n; ++i)
  {
    this->Nodes[i].active = 0;
    this->Nodes[i].timestamp = 0;
    this->Nodes[i].distance = 1;
    this->Nodes[i].inSinkTree = this->TerminalCapacity[i] < 0.0 ? 1 : 0;
    this->Nodes[i].parent = this->TerminalCapacity[i] != 0.0 ? TerminalParent : NoParent;
    if (this->Nodes[i].parent == TerminalParent)
    {
      this->MakeActive(static_cast<std::int32_t>(i));
    }
  }
  std::int32_t current = -1;
  while (true)
  {
    std::int32_t node = current;
    if (node < 0 || this->Nodes[static_cast<std::size_t>(node)].parent == NoParent)
    {
      node = this->NextActive();
      if (node < 0)
      {
        break;
      }
    }
    current = -1;
    std::int32_t meetingArc = -1;
    if (!this->Grow(node, meetingArc))
    {
      continue; // no path through this node any more
    }
    ++this->Time;
    this->Augment(meetingArc);
    while (true)
    {
      std::int32_t orphan = -1;
      if (!this->NewOrphans.empty())
      {
        orphan = this->NewOrphans.back();
        this->NewOrphans.pop_back();
      }
      else if (this->OrphanHead < this->OrphanQueue.size())
      {
        orphan = this->OrphanQueue[this->OrphanHead++];
      }
      else
      {
        break;
      }
      this->Adopt(orphan);
    }
    this->OrphanQueue.clear();
    this->OrphanHead = 0;
    current = node; // it may reach the other tree again
  }
  return this->FlowValue;
}

} // namespace shapediameter
